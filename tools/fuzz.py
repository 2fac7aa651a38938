#!/usr/bin/python3
"""make fuzz: mutated decks through the reader and the first cycles.

    fuzz.py [--seconds S] [--seed N] [--keep DIR] [--timeout T]

Takes the decks of tests/ and input_decks/ (single files, no includes),
mutates each at random (a byte flipped, a field replaced by NaN, Inf, a
huge or tiny number, a negative id, garbage, a card dropped or doubled, the
file cut short, a keyword renamed, or the deck split into a main file and
an *INCLUDE, itself mutated, or an include of a missing file, a directory,
/dev/null or the deck itself) and runs bin/xdyna on it through the reader,
the checks and its first 30 cycles (endcyc=30). Each outcome falls in one
class:

    valid     exit 0, normal termination, and every glstat row possible:
              finite, the energy ratio in [0, 1.5] (the default ENDENG
              band's top; its bottom 1/1.5 holds from the tenth cycle, which
              a row's time does not tell) and the kinetic energy, the product
              1/2 m v(n-1/2).v(n+1/2), not below minus half the initial
              energy plus external work (it dips below zero where nodes turn
              round; the run itself stops on three such cycles in a row). A
              run that accepted an impossible state silently is a FAIL.
    input     exit 1 naming the file (and the line, where there is one)
    run       exit 2 with a named cause ('error termination')
    signal    exit 3 (not expected here)
    FAIL      anything else: a crash (signal), a hang (timeout), exit 1 or 2
              without the promised message, exit 0 without normal termination

A fifth of the time (--dump-share) goes to damaged restart dumps: a small
dump (the bar on a wall) with one byte changed, the positions taken in a
stride that covers the whole file, then at random, each run with r=: the
only right answer is exit 1 naming the checksum; and to the files that are
no files: a FIFO as r=, as an *INCLUDE and as an output (glstat) in outdir=,
each answered with exit 1 within the timeout.

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


def mutate(text, rng, work=None):
    """A mutated deck (its text) and the mutation's name; with `work`, it may
    come as a main file that includes a second one written there."""
    lines = text.split("\n")
    kinds = ["field", "field", "field", "byte", "drop", "double", "cut", "keyword"]
    kind = rng.choice(kinds + (["include", "include_odd"] if work else []))
    kws = [i for i, l in enumerate(lines) if l.startswith("*") and not l.upper().startswith(("*KEYWORD", "*END"))]
    if kind == "include" and kws:
        # the deck's tail, mutated, in an include file
        i = rng.choice(kws)
        tail, sub = mutate("\n".join(lines[i:]), rng)
        part = os.path.join(work, "part.k")
        with open(part, "w") as fh:
            fh.write(tail)
        return "\n".join(lines[:i] + ["*INCLUDE", rng.choice(["part.k", part])] + ["*END"]), "include+" + sub
    if kind == "include_odd" and kws:
        i = rng.choice(kws)
        target = rng.choice(["missing.k", work, "/dev/null", "case.k", "", "part.k " * 40])
        return "\n".join(lines[:i] + ["*INCLUDE", target] + lines[i:]), "include_odd"
    if kind.startswith("include"):
        kind = "field"
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


def impossible_state(outdir):
    """What is impossible in a finished run's glstat rows ('' if nothing):
    a value not finite, or a negative kinetic energy."""
    path = os.path.join(outdir, "thist.h5")
    if not os.path.exists(path):
        return ""
    try:
        import h5py
        import numpy as np
    except ImportError:
        return ""
    try:
        with h5py.File(path, "r") as f:
            if "glstat" not in f:
                return ""
            g = f["glstat"]
            for name in g:
                if isinstance(g[name], h5py.Dataset) and not np.all(np.isfinite(g[name][()])):
                    return f"glstat {name} not finite"
            ratio = g["energy_ratio"][()]
            if np.any(ratio < 0.0) or np.any(ratio > 1.5 * (1 + 1e-9)):
                return f"energy ratio {ratio.min():.4g} .. {ratio.max():.4g} outside [0, 1.5]"
            ke = g["kinetic_energy"][()]
            scale = abs(g["total_energy"][0]) + abs(g["external_work"][()])
            if np.any(ke < -0.5 * scale):
                return "kinetic energy below minus half the initial energy plus external work"
    except (OSError, KeyError) as err:
        return f"thist.h5 unreadable: {err}"
    return ""


def classify(p, timeout, outdir=None):
    if p is None:
        return "FAIL", "hang (timeout)"
    out = p.stdout + p.stderr
    if p.returncode == 0:
        if "normal termination" not in out:
            return "FAIL", "exit 0 without normal termination"
        bad = impossible_state(outdir) if outdir else ""
        return ("FAIL", "normal termination of an impossible state: " + bad) if bad else ("valid", "")
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


def damaged_dumps(seconds, rng, work, keep, timeout):
    """Restart dumps with one byte changed, and FIFOs where files belong,
    for `seconds`: (cases, counts by class: refused, FAIL)."""
    counts = {}
    base = os.path.join(work, "dumps")
    shutil.rmtree(base, ignore_errors=True)
    os.makedirs(base)
    deck = os.path.join(base, "dumped.k")
    with open(os.path.join(ROOT, "input_decks", "verify", "bar_wall.k")) as fh:
        text = fh.read()
    with open(deck, "w") as fh:
        fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n*DATABASE_BINARY_D3DUMP\n         0\n", 1))
    out = os.path.join(base, "run")
    subprocess.run([XDYNA, "i=" + deck, "outdir=" + out, "endtim=2e-5"], capture_output=True, timeout=60)
    dump = os.path.join(out, "d3dump.h5")
    if not os.path.exists(dump):
        return 0, {"FAIL": 1}
    good = open(dump, "rb").read()

    def answer(args, cwd=None):
        try:
            return subprocess.run([XDYNA, *args], capture_output=True, text=True, timeout=timeout, cwd=cwd,
                                  errors="replace")
        except subprocess.TimeoutExpired:
            return None

    def note(cls, what, p):
        counts[cls] = counts.get(cls, 0) + 1
        if cls == "FAIL":
            with open(os.path.join(keep, f"dump_{sum(counts.values()):05d}.txt"), "w") as fh:
                fh.write(what + "\n" + ("hang" if p is None else f"exit {p.returncode}\n{p.stdout[-1000:]}"
                                       f"\n{p.stderr[-1000:]}"))
            print(f"FAIL {what}", flush=True)

    # files that are no files: each must be refused at once
    fifo = os.path.join(base, "fifo")
    os.mkfifo(fifo)
    p = answer(["r=" + fifo])
    note("refused" if p is not None and p.returncode == 1 else "FAIL", "r= a FIFO", p)
    inc = os.path.join(base, "inc.k")
    with open(inc, "w") as fh:
        fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n*INCLUDE\n" + fifo + "\n", 1))
    p = answer(["i=" + inc, "outdir=" + os.path.join(base, "inc_out")])
    note("refused" if p is not None and p.returncode == 1 else "FAIL", "*INCLUDE of a FIFO", p)
    fo = os.path.join(base, "fifo_out")
    os.makedirs(fo)
    os.mkfifo(os.path.join(fo, "glstat"))
    p = answer(["i=" + deck, "outdir=" + fo, "endtim=1e-6"])
    note("refused" if p is not None and p.returncode == 1 else "FAIL", "a FIFO as glstat in outdir=", p)
    # one byte changed: a stride over the whole file first, then at random
    n = len(good)
    stride = max(1, n // 64)
    order = list(range(0, n, stride))
    t0 = time.time()
    k = 0
    bad = os.path.join(base, "bad.h5")
    while time.time() - t0 < seconds:
        at = order[k] if k < len(order) else rng.randrange(n)
        k += 1
        data = bytearray(good)
        data[at] ^= rng.randrange(1, 256)
        with open(bad, "wb") as fh:
            fh.write(data)
        elsewhere = os.path.join(base, "cwd")
        shutil.rmtree(elsewhere, ignore_errors=True)
        os.makedirs(elsewhere)
        p = answer(["r=" + bad, "endtim=4e-5"], cwd=elsewhere)
        refused = p is not None and p.returncode == 1 and "checksum" in p.stderr and os.listdir(elsewhere) == []
        note("refused" if refused else "FAIL", f"dump byte {at} of {n} changed", p)
    return k + 3, counts


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", default=os.path.join(ROOT, "build", "fuzz", "failures"))
    ap.add_argument("--timeout", type=float, default=30)
    ap.add_argument("--summary", help="also write the counts to this file")
    ap.add_argument("--dump-share", type=float, default=0.2, help="share of the time for damaged dumps and FIFOs")
    args = ap.parse_args(argv)
    rng = random.Random(args.seed)
    pool = decks()
    work = os.path.join(ROOT, "build", "fuzz", "work")
    os.makedirs(work, exist_ok=True)
    os.makedirs(args.keep, exist_ok=True)
    counts = {}
    n = 0
    t0 = time.time()
    while time.time() - t0 < (1 - args.dump_share) * args.seconds:
        src, text = rng.choice(pool)
        mutated, kind = mutate(text, rng, work)
        n += 1
        deck = os.path.join(work, "case.k")
        with open(deck, "w") as fh:
            fh.write(mutated)
        out = os.path.join(work, "out")
        shutil.rmtree(out, ignore_errors=True)
        cmd = [XDYNA, "i=" + deck, "outdir=" + out, "endcyc=30", "ncpu=1"]
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout,
                               env=dict(os.environ, OMP_NUM_THREADS="1"), errors="replace")
        except subprocess.TimeoutExpired:
            p = None
        cls, why = classify(p, args.timeout, out)
        counts[cls] = counts.get(cls, 0) + 1
        if cls == "FAIL":
            keep = os.path.join(args.keep, f"case{n:05d}.k")
            shutil.copy(deck, keep)
            if kind.startswith("include") and os.path.exists(os.path.join(work, "part.k")):
                shutil.copy(os.path.join(work, "part.k"), keep[:-2] + "_part.k")
            with open(keep + ".txt", "w") as fh:
                fh.write(f"from {os.path.relpath(src, ROOT)}, mutation {kind}: {why}\n")
                if p is not None:
                    fh.write(p.stdout[-2000:] + "\n" + p.stderr[-2000:])
            print(f"FAIL case {n} ({os.path.relpath(src, ROOT)}, {kind}): {why}", flush=True)
    t1 = time.time()
    nd, dcounts = damaged_dumps(args.dump_share * args.seconds, rng, work, args.keep, args.timeout)
    line = (f"fuzz: {n} mutated decks in {t1 - t0:.0f} s (seed {args.seed}): " +
            ", ".join(f"{k} {v}" for k, v in sorted(counts.items())) +
            f"; {nd} damaged dumps and FIFOs in {time.time() - t1:.0f} s: " +
            ", ".join(f"{k} {v}" for k, v in sorted(dcounts.items())))
    for k, v in dcounts.items():
        if k == "FAIL":
            counts["FAIL"] = counts.get("FAIL", 0) + v
    print(line)
    if args.summary:
        with open(args.summary, "w") as fh:
            fh.write(line + "\n")
    return 1 if counts.get("FAIL") else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
