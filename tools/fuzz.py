#!/usr/bin/python3
"""make fuzz: mutated decks through the reader and the first cycles.

    fuzz.py [--seconds S] [--seed N] [--keep DIR] [--timeout T]

Takes the decks of tests/ and input_decks/ (single files, no includes),
mutates each at random (a byte flipped, a field replaced by NaN, Inf, a
huge or tiny number, a negative id, garbage, a card dropped or doubled, the
file cut short, a keyword renamed) and runs bin/xdyna on it through the
reader, the checks and the first cycle (endtim 1e-9). Each outcome
falls in one class:

    valid     exit 0, normal termination
    input     exit 1 naming the file (and the line, where there is one)
    run       exit 2 with a named cause ('error termination')
    signal    exit 3 (not expected here)
    FAIL      anything else: a crash (signal), a hang (timeout), exit 1 or 2
              without the promised message, exit 0 without normal termination

The failing decks are kept (--keep, default build/fuzz/failures) with the
command and its output, to become regression decks. Prints the counts per
class; exit 1 when any FAIL was seen.
"""
import argparse
import glob
import os
import random
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
XDYNA = os.path.join(ROOT, "bin", "xdyna")
VALUES = ["nan", "NaN", "inf", "-inf", "1e999", "-1e999", "1e-320", "1e300", "-1e300", "0", "-1",
          "99999999", "-99999999", "1.0e+", "abc", "&nope", "*", ",,,", "1e30", "-0"]


def decks():
    found = []
    for pat in ("tests/decks/**/*.k", "input_decks/**/*.k"):
        for p in glob.glob(os.path.join(ROOT, pat), recursive=True):
            text = open(p, errors="replace").read()
            if "*INCLUDE" in text.upper() or len(text) > 400000:
                continue
            found.append((p, text))
    return found


def mutate(text, rng):
    lines = text.split("\n")
    kind = rng.choice(["field", "field", "field", "byte", "drop", "double", "cut", "keyword"])
    data = [i for i, l in enumerate(lines) if l.strip() and not l.startswith(("$", "*"))]
    if kind == "field" and data:
        i = rng.choice(data)
        l = lines[i].ljust(80)
        w = 16 if re.match(r"\s*\d+\s+[-\d.eE+]+\s+[-\d.eE+]+\s+[-\d.eE+]+", l) and len(l.rstrip()) > 60 else 10
        k = rng.randrange(0, 8)
        v = rng.choice(VALUES)
        lines[i] = (l[:k * w] + v.rjust(w)[:w] + l[(k + 1) * w:]).rstrip()
    elif kind == "byte":
        s = bytearray(text.encode())
        if s:
            j = rng.randrange(len(s))
            s[j] = rng.randrange(1, 256)
        return s.decode(errors="replace"), kind
    elif kind == "drop" and data:
        del lines[rng.choice(data)]
    elif kind == "double" and data:
        i = rng.choice(data)
        lines.insert(i, lines[i])
    elif kind == "cut":
        return text[:rng.randrange(len(text) + 1)], kind
    elif kind == "keyword":
        kws = [i for i, l in enumerate(lines) if l.startswith("*") and not l.upper().startswith(("*KEYWORD", "*END"))]
        if kws:
            i = rng.choice(kws)
            lines[i] = lines[i] + rng.choice(["_X", "_ID", "_TITLE", "S", ""])
    return "\n".join(lines), kind


def classify(p, timeout):
    if p is None:
        return "FAIL", "hang (timeout)"
    out = p.stdout + p.stderr
    if p.returncode == 0:
        return ("valid", "") if "normal termination" in out else ("FAIL", "exit 0 without normal termination")
    if p.returncode == 1:
        # file:line, or the deck's file for what concerns the whole deck
        # (no nodes, no *CONTROL_TERMINATION)
        return ("input", "") if re.search(r"\S+\.k(:\d+)?:", p.stderr) or "xdyna:" in p.stderr else \
            ("FAIL", "exit 1 without naming the file")
    if p.returncode == 2:
        return ("run", "") if "error termination" in out else ("FAIL", "exit 2 without a cause")
    if p.returncode == 3:
        return "signal", ""
    return "FAIL", f"exit {p.returncode}"


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", default=os.path.join(ROOT, "build", "fuzz", "failures"))
    ap.add_argument("--timeout", type=float, default=30)
    args = ap.parse_args(argv)
    rng = random.Random(args.seed)
    pool = decks()
    work = os.path.join(ROOT, "build", "fuzz", "work")
    os.makedirs(work, exist_ok=True)
    os.makedirs(args.keep, exist_ok=True)
    counts = {}
    n = 0
    t0 = time.time()
    while time.time() - t0 < args.seconds:
        src, text = rng.choice(pool)
        mutated, kind = mutate(text, rng)
        n += 1
        deck = os.path.join(work, "case.k")
        with open(deck, "w") as fh:
            fh.write(mutated)
        out = os.path.join(work, "out")
        shutil.rmtree(out, ignore_errors=True)
        cmd = [XDYNA, "i=" + deck, "outdir=" + out, "endtim=1e-9", "ncpu=1"]
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout,
                               env=dict(os.environ, OMP_NUM_THREADS="1"), errors="replace")
        except subprocess.TimeoutExpired:
            p = None
        cls, why = classify(p, args.timeout)
        counts[cls] = counts.get(cls, 0) + 1
        if cls == "FAIL":
            keep = os.path.join(args.keep, f"case{n:05d}.k")
            shutil.copy(deck, keep)
            with open(keep + ".txt", "w") as fh:
                fh.write(f"from {os.path.relpath(src, ROOT)}, mutation {kind}: {why}\n")
                if p is not None:
                    fh.write(p.stdout[-2000:] + "\n" + p.stderr[-2000:])
            print(f"FAIL case {n} ({os.path.relpath(src, ROOT)}, {kind}): {why}", flush=True)
    print(f"fuzz: {n} mutated decks in {time.time() - t0:.0f} s (seed {args.seed}): " +
          ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    return 1 if counts.get("FAIL") else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
