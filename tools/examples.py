#!/usr/bin/python3
"""The paper's three examples (section 7): run, check, draw, tabulate.

    examples.py [--only NAME ...] [--no-knobs] [--threads N] [--out DIR]

For each deck of input_decks/paper/ (wide_flange_beam, wall_of_blocks,
front_frame): a run with the default contact settings, then (unless
--no-knobs) the same deck with the search knobs the paper discusses
(*CONTROL_XDYNA_CONTACT: global search every cycle, adaptive; master node
lists of the closest node, the three closest). Every run is checked by the
penetration checker (tools/penetration.py, independent of the contact
code) and its energies are read from thist.h5. The default runs are drawn
(four deformed states and the time histories) into doc/examples/, and the
tables between the markers of doc/examples.md are rewritten. Runs go to
out/examples/ (one thread each unless --threads: the timings are single-
core figures, to set against the paper's single CPU).

Exit 0 when every run finished and its default run met the checks (energy
ratio within 5%, penetration below 20% of the local thickness); 1
otherwise. The hourglass energy of every deformable part is reported
against 10% of its largest internal energy (a mark, not a failure: see
doc/examples.md).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# the runs' states also in d3plot.h5, which this tool reads (the d3plot
# family in LS-DYNA's layout is written as well)
os.environ.setdefault("XDYNA_H5PLOT", "1")
sys.path.insert(0, os.path.join(ROOT, "tools"))
import penetration  # noqa: E402

XD = os.path.join(ROOT, "bin", "xdyna")
PY = "/usr/bin/python3"

EXAMPLES = {
    "wide_flange_beam": {"title": "7.1 Wide-flange beam crush", "times": [0.0, 0.012, 0.016, 0.02],
                         "view": [8, 20], "color": "part"},
    "wall_of_blocks": {"title": "7.2 Wall of blocks", "times": [0.0, 0.01, 0.025, 0.04],
                       "view": [20, -60], "color": "part"},
    "front_frame": {"title": "7.3 Vehicle front frame", "times": [0.0, 0.005, 0.015, 0.03],
                    "view": [20, 70], "color": "part"},
}

# name: (what it is, *CONTROL_XDYNA_CONTACT card or None)
KNOBS = [("default", "the default: search when 4u > delta, minimal master node set", None),
         ("interval_1", "global search every cycle", "         1         1"),
         ("adaptive", "adaptive search interval (4u > delta)", "         2"),
         ("closest_1", "master node list: the closest node", "         0         0         1"),
         ("closest_3", "master node list: the three closest nodes", "         0         0         3")]

LIMITS = {"energy": 0.05, "hourglass": 0.10, "penetration": 0.20}


def deck_with(deck, card, path):
    """Copy of deck with *CONTROL_XDYNA_CONTACT card added after *KEYWORD."""
    lines = open(deck).read().splitlines()
    out = []
    for ln in lines:
        out.append(ln)
        if ln.strip().upper() == "*KEYWORD" and card is not None:
            out += ["*CONTROL_XDYNA_CONTACT", card]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def parse_d3hsp(path):
    """Timing table, contact share, cycles and search summary of a log."""
    txt = open(path).read()
    res = {"phases": {}}
    for m in re.finditer(r"^\s{3}([a-z][a-z ]+?)\s{2,}([0-9.]+)\s+([0-9.]+)\s*$", txt, re.M):
        res["phases"][m.group(1).strip()] = float(m.group(2))
    m = re.search(r"^\s+total\s+([0-9.]+)\s*$", txt, re.M)
    res["total"] = float(m.group(1)) if m else float("nan")
    m = re.search(r"contact share of the time loop \.+\s+([0-9.]+) %", txt)
    res["contact_share"] = float(m.group(1)) / 100 if m else 0.0
    m = re.search(r"cycles \.+\s+(\d+)", txt)
    res["cycles"] = int(m.group(1)) if m else 0
    m = re.search(r"time per zone cycle \(nanosec\) \.+\s+([0-9.]+)", txt)
    res["ns_zone_cycle"] = float(m.group(1)) if m else float("nan")
    m = re.search(r"^\s+1\s+(\d+)\s+(\d+)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)\s*$",
                  txt, re.M)
    if m:
        res["searches"] = int(m.group(2))
        res["masters_per_slave"] = float(m.group(3))
        res["max_4u_delta"] = float(m.group(8))
    m = re.search(r"interface 1: (\d+) (?:missed )?contacts found .*?largest excess\s+([0-9.Ee+-]+)", txt, re.S)
    res["late"] = int(m.group(1)) if m else 0
    res["late_excess"] = float(m.group(2)) if m else 0.0
    return res


def energies(run):
    """Energy figures from thist.h5: the ratio's worst departure from 1,
    the final energies, and hourglass / internal energy per deformable part
    at the end."""
    with h5py.File(os.path.join(run, "thist.h5"), "r") as f:
        g = f["glstat"]
        ratio = g["energy_ratio"][:]
        # the same once 1% of the energy is in (at the very start the ratio
        # of two tiny numbers swings: the beam's pressure has done 0.3 mJ)
        put_in = np.maximum(g["kinetic_energy"][0] + g["internal_energy"][0], 0.0) + np.maximum(g["external_work"][:], 0)
        ready = put_in >= 0.01 * put_in.max()
        e = {"ratio_end": float(ratio[-1]), "ratio_dev": float(np.max(np.abs(ratio - 1.0))),
             "ratio_dev_in": float(np.max(np.abs(ratio[ready] - 1.0))), "put_in": float(put_in.max()),
             "kinetic0": float(g["kinetic_energy"][0]), "kinetic": float(g["kinetic_energy"][-1]),
             "internal": float(g["internal_energy"][-1]), "hourglass": float(g["hourglass_energy"][-1]),
             "sliding": float(g["sliding_interface_energy"][-1]),
             "sliding_min": float(np.min(g["sliding_interface_energy"][:])),
             "external": float(g["external_work"][-1]), "stonewall": float(g["stonewall_energy"][-1]) if "stonewall_energy" in g else 0.0,
             "total": float(g["total_energy"][-1])}
        m = f["matsum"]
        ids = m["ids"][:]
        ie = m["internal_energy"][-1]
        iemax = np.max(m["internal_energy"][:], axis=0)
        hg = m["hourglass_energy"][-1]
        parts = {}
        for k, pid in enumerate(ids):
            if iemax[k] > 0.0:
                parts[int(pid)] = {"internal": float(ie[k]), "internal_max": float(iemax[k]),
                                   "hourglass": float(hg[k]), "share": float(hg[k] / iemax[k])}
        e["parts"] = parts
        e["hg_share_max"] = max((p["share"] for p in parts.values()), default=0.0)
    return e


def run_one(deck, outdir, threads, endtim=None):
    os.makedirs(outdir, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    cmd = [XD, f"i={deck}", f"outdir={outdir}"]
    if endtim:
        cmd.append(f"endtim={endtim}")
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - t0
    res = {"rc": p.returncode, "wall": wall}
    if p.returncode != 0:
        res["tail"] = p.stdout[-2000:]
        return res
    res.update(parse_d3hsp(os.path.join(outdir, "d3hsp")))
    res["energy"] = energies(outdir)
    worst, crossings, nstate, t_worst = penetration.check_run(outdir)
    res["penetration"] = {"worst": worst, "pass_throughs": crossings, "states": nstate, "time": t_worst,
                          "node": penetration.where[0] if penetration.where else None}
    with h5py.File(os.path.join(outdir, "d3plot.h5"), "r") as f:
        last = sorted(k for k in f["states"] if k != "time")[-1]
        res["x_end"] = f[f"states/{last}/coordinates"][:].tolist()
    return res


def contact_time(r):
    ph = r["phases"]
    return sum(ph.get(k, 0.0) for k in ("contact global search", "contact local search", "contact enforcement"))


def ok_checks(r):
    """Energy ratio and penetration within their limits (the hourglass share
    is reported against its 10% mark separately: see hg_note)."""
    e = r["energy"]
    return r["rc"] == 0 and e["ratio_dev"] <= LIMITS["energy"] and r["penetration"]["worst"] <= LIMITS["penetration"]


def hg_note(r):
    over = [pid for pid, p in sorted(r["energy"]["parts"].items()) if p["share"] > LIMITS["hourglass"]]
    return "under 10% in every part" if not over else "over 10% in part " + ", ".join(map(str, over))


def draw(name, run, spec):
    os.makedirs(os.path.join(ROOT, "doc", "examples"), exist_ok=True)
    mesh = os.path.join(ROOT, "doc", "examples", f"{name}_states.png")
    hist = os.path.join(ROOT, "doc", "examples", f"{name}_histories.png")
    subprocess.run([PY, os.path.join(ROOT, "tools", "xdplot.py"), "mesh", run, "--times",
                    *[str(t) for t in spec["times"]], "--view", *[str(v) for v in spec["view"]],
                    "--color", spec["color"], "--out", mesh], check=True, stdout=subprocess.DEVNULL)
    subprocess.run([PY, os.path.join(ROOT, "tools", "xdplot.py"), "history", run, "--out", hist], check=True,
                   stdout=subprocess.DEVNULL)


def tables(results):
    """Markdown tables of all runs."""
    out = ["### Default settings (one thread)", "",
           "| example | elements | cycles | run time (s) | contact share | ns per element-cycle | energy ratio: "
           "worst departure (once 1% of the energy is in) | hourglass / internal, worst part | sliding energy "
           "at the end, of the energy put in (J) | "
           "largest penetration (of the local thickness) | pass-throughs | energy and penetration checks | hourglass |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    part_rows = []
    for name, rs in results.items():
        r = rs.get("default")
        if not r or r["rc"] != 0:
            out.append(f"| {name} | | | failed (exit {r['rc'] if r else '?'}) | | | | | | | | no | |")
            continue
        for pid, p in sorted(r["energy"]["parts"].items()):
            part_rows.append(f"| {name} | {pid} | {p['internal']:.1f} | {p['internal_max']:.1f} | "
                             f"{p['hourglass']:.2f} | {p['share'] * 100:.2f}% |")
        e = r["energy"]
        out.append(f"| {EXAMPLES[name]['title']} | {r['elements']} | {r['cycles']} | {r['total']:.1f} | "
                   f"{r['contact_share'] * 100:.1f}% | {r['ns_zone_cycle']:.0f} | {e['ratio_dev']:.2e} "
                   f"({e['ratio_dev_in']:.2e}) | {e['hg_share_max'] * 100:.2f}% | {e['sliding']:.1f} of "
                   f"{e['put_in']:.0f} | {r['penetration']['worst'] * 100:.1f}% | {r['penetration']['pass_throughs']} | "
                   f"{'pass' if ok_checks(r) else 'FAIL'} | {hg_note(r)} |")
    out += ["", "### Energy per part (default settings)", "",
            "Hourglass energy at the end over the largest internal energy the part had (an elastic part gives "
            "its strain energy back to motion: at the end its internal energy is near zero).", "",
            "| example | part | internal at the end (J) | largest internal (J) | hourglass at the end (J) | "
            "hourglass / largest internal |", "|---|---|---|---|---|---|"] + part_rows
    if any(len(rs) > 1 for rs in results.values()):
        out += ["", "### Search knobs (one thread)", "",
                "Difference: the largest distance of a node at the end from where the run with a global "
                "search every cycle puts it.", "",
                "| example | setting | run time (s) | contact (s) | global searches | masters per slave | "
                "max 4u/delta | contacts allowed late | largest penetration | energy ratio: worst departure | "
                "difference (m) |",
                "|---|---|---|---|---|---|---|---|---|---|---|"]
        for name, rs in results.items():
            ref = rs.get("interval_1")
            for knob, what, _ in KNOBS:
                r = rs.get(knob)
                if not r:
                    continue
                if r["rc"] != 0:
                    out.append(f"| {name} | {what} | failed (exit {r['rc']}) | | | | | | | | |")
                    continue
                diff = ""
                if ref and ref["rc"] == 0:
                    diff = f"{np.max(np.linalg.norm(np.array(r['x_end']) - np.array(ref['x_end']), axis=1)):.3g}"
                out.append(f"| {name} | {what} | {r['total']:.1f} | {contact_time(r):.2f} | {r.get('searches', 0)} | "
                           f"{r.get('masters_per_slave', 0):.2f} | {r.get('max_4u_delta', 0):.3f} | {r['late']} | "
                           f"{r['penetration']['worst'] * 100:.1f}% | {r['energy']['ratio_dev']:.2e} | {diff} |")
    return "\n".join(out)


def element_count(deck):
    n, kw = 0, None
    for ln in open(deck):
        if ln.startswith("*"):
            kw = ln.split()[0].upper()
        elif kw in ("*ELEMENT_SHELL", "*ELEMENT_SOLID") and not ln.startswith("$"):
            n += 1
    return n


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", nargs="*", default=list(EXAMPLES))
    ap.add_argument("--no-knobs", action="store_true")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "examples"))
    ap.add_argument("--no-doc", action="store_true", help="do not draw nor rewrite doc/examples.md")
    args = ap.parse_args()
    results = {}
    status = 0
    for name in args.only:
        deck = os.path.join(ROOT, "input_decks", "paper", name + ".k")
        results[name] = {}
        for knob, what, card in KNOBS:
            if knob != "default" and args.no_knobs:
                continue
            run = os.path.join(args.out, name if knob == "default" else f"{name}_{knob}")
            d = deck
            if card is not None:
                os.makedirs(run, exist_ok=True)
                d = os.path.join(run, name + ".k")
                deck_with(deck, card, d)
            r = run_one(d, run, args.threads)
            r["elements"] = element_count(deck)
            results[name][knob] = r
            if r["rc"] != 0:
                print(f"examples: {name} ({what}): exit {r['rc']}\n{r.get('tail', '')}")
                status = 1
                continue
            e, p = r["energy"], r["penetration"]
            print(f"examples: {name:17s} {knob:11s} {r['total']:6.1f} s, contact {r['contact_share'] * 100:4.1f}%, "
                  f"energy ratio off by {e['ratio_dev']:.1e}, hourglass {e['hg_share_max'] * 100:.2f}% "
                  f"(worst part), penetration {p['worst'] * 100:.1f}% (node {p['node']}), "
                  f"pass-throughs {p['pass_throughs']}")
            if knob == "default":
                if not ok_checks(r):
                    print(f"examples: {name}: a check failed (limits: energy ratio within "
                          f"{LIMITS['energy']:.0%}, penetration below {LIMITS['penetration']:.0%} of the local "
                          f"thickness)")
                    status = 1
                print(f"examples: {name}: hourglass energy {hg_note(r)} (mark: 10% of the part's largest "
                      f"internal energy)")
                if not args.no_doc:
                    draw(name, run, EXAMPLES[name])
    summary = os.path.join(args.out, "summary.json")
    os.makedirs(args.out, exist_ok=True)
    tab = tables(results)
    with open(summary, "w") as f:
        json.dump({n: {k: {kk: vv for kk, vv in r.items() if kk != "x_end"} for k, r in rs.items()}
                   for n, rs in results.items()}, f, indent=1)
    print(tab)
    doc = os.path.join(ROOT, "doc", "examples.md")
    if not args.no_doc and os.path.exists(doc) and set(args.only) == set(EXAMPLES):
        txt = open(doc).read()
        a, b = "<!-- results:begin -->", "<!-- results:end -->"
        if a in txt and b in txt:
            txt = txt[:txt.index(a) + len(a)] + "\n" + tab + "\n" + txt[txt.index(b):]
            with open(doc, "w") as f:
                f.write(txt)
            print(f"examples: tables written to {doc}")
    print(f"examples: summary in {summary}")
    return status


if __name__ == "__main__":
    sys.exit(main())
