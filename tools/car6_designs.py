#!/usr/bin/python3
"""car6's designs against LS-DYNA (issue 28): the first 16 designs of the
deck owners' Latin-hypercube sample, run as published (xdyna's default
bounded stiffness-form hourglass) and again with elastic hourglass springs
(*CONTROL_XDYNA_SHELL HGBOUND 0), each set against LS-DYNA's answers for
the same design.

    car6_designs.py [--jobs N] [--only N]

The designs and LS-DYNA's answers are the public data of the deck's owners
(GitHub dbrizard/GSA-car-crash: LHS/4param/LHS-100_X.csv, the design
parameters tbumper, trailb, trailf (mm) and yrailf (MPa);
LHS-100_Y_dmax.csv, node 605's largest x-displacement (mm); LHS-100_Y_fmax.csv,
the post's largest force (N)), copied here as numbers. Each design is
../shared/public-decks/car6_main.k with those four *PARAMETER values
changed, including car6_crash_v223.k unchanged; xdyna's crush is node 605's
least x-displacement over the run (nodout), its force the largest x-force
on rigid wall 2 (rwforc). One thread a run, --jobs runs at a time (2).
Writes doc/car6-designs.md and prints its rows.
"""
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DECKS = os.path.join(os.path.dirname(ROOT), "shared", "public-decks")
XDYNA = os.path.join(ROOT, "bin", "xdyna")
OUT = os.path.join(ROOT, "build", "car6-designs")
REPORT = os.path.join(ROOT, "doc", "car6-designs.md")

# (tbumper mm, trailb mm, trailf mm, yrailf MPa, LS-DYNA dmax mm, LS-DYNA fmax N)
DESIGNS = [
    (2.705241961919426, 1.011698622234320, 4.657610163327230, 407.5196512184916, -724.76025390625, 728761.3125),
    (2.027677100698454, 2.886385985906569, 4.566670431034182, 334.7150129034802, -706.92150878906, 589988.8750),
    (2.146429020994614, 2.198344709796805, 3.886222960772347, 424.2442095705680, -762.19140625000, 583777.1875),
    (2.067978889347362, 2.837160021720816, 6.533117937440041, 371.6469125893359, -595.07452392578, 855715.1875),
    (2.651133706919655, 1.864662883591598, 3.065163977858003, 331.9277050676118, -851.89984130859, 436316.3750),
    (3.320918311539658, 2.855798768565891, 4.133685176484219, 455.7541257405240, -530.81878662109, 707138.0000),
    (2.556917318995124, 2.554349414695513, 6.873001191122578, 464.2707197546951, -462.74700927734, 1022862.875),
    (2.912357190498005, 2.423088041811449, 6.809924014827288, 482.2944819956131, -425.12332153320, 1090600.625),
    (2.870987102728211, 2.566004683166233, 3.814060355592205, 347.2764503313153, -738.42700195312, 541365.2500),
    (3.544256775677717, 1.282381716636603, 6.664266764152391, 405.2135544614035, -541.42779541016, 943120.2500),
    (2.636363177426509, 1.932892639193487, 5.193779839286391, 495.9008305869013, -605.57928466797, 887395.8125),
    (2.661714818741715, 1.228266535728905, 3.191530322540223, 390.4742768260485, -813.01000976562, 531528.0625),
    (2.448142753813280, 1.716332908734364, 6.760268717464859, 452.2404403411809, -521.41088867188, 993207.8750),
    (3.804681043511973, 2.313420709056689, 4.424636941198251, 365.3145826041850, -513.04278564453, 653987.3750),
    (3.357134195626612, 2.700009165348708, 4.821911549798651, 383.7857117974320, -507.47735595703, 707770.5625),
    (2.333573898885834, 2.225995729278968, 4.782730278849410, 413.0931978123602, -688.73028564453, 732242.0625),
]


def post_force_and_node605(h5):
    """car6's histories in thist.h5 `h5`: the x-force on the post (rwforc,
    wall 2) and node 605's x-displacement (nodout), over the outputs."""
    with h5py.File(h5, "r") as f:
        rw, n = f["rwforc"], f["nodout"]
        return (rw["x_force"][:, list(rw["ids"][:]).index(2)],
                n["x_displacement"][:, list(n["ids"][:]).index(605)])


def design_deck(i, elastic):
    """Design i's main deck (the four parameters changed; HGBOUND 0 added
    where `elastic`), written in OUT, including the published crash deck."""
    tb, trb, trf, yrf = DESIGNS[i][:4]
    with open(os.path.join(DECKS, "car6_main.k")) as f:
        s = f.read()
    for old, new in (("r  tbumper         3", f"r  tbumper{tb:10.5f}"), ("rtrailb         2", f"rtrailb{trb:10.5f}"),
                     ("rtrailf         5", f"rtrailf{trf:10.5f}"), ("ryrailf       400", f"ryrailf{yrf:10.4f}")):
        if old not in s:
            raise SystemExit(f"car6_main.k: '{old}' not found (the published deck changed?)")
        s = s.replace(old, new)
    s = s.replace("car6_crash_v223.k", os.path.join(DECKS, "car6_crash_v223.k"))
    if elastic:
        s = s.replace("*KEYWORD\n", "*KEYWORD\n*CONTROL_XDYNA_SHELL\n         0\n", 1)
    path = os.path.join(OUT, f"design{i:02d}{'_elastic' if elastic else ''}.k")
    with open(path, "w") as f:
        f.write(s)
    return path


def run(i, elastic):
    deck = design_deck(i, elastic)
    out = deck[:-2]
    p = subprocess.run([XDYNA, "i=" + deck, "outdir=" + out], capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    if p.returncode != 0:
        return None
    fx, ux = post_force_and_node605(os.path.join(out, "thist.h5"))
    return float(ux.min()), float(fx.max())


def main(argv):
    jobs = int(argv[argv.index("--jobs") + 1]) if "--jobs" in argv else 2
    sel = [int(argv[argv.index("--only") + 1])] if "--only" in argv else list(range(len(DESIGNS)))
    os.makedirs(OUT, exist_ok=True)
    tasks = [(i, b) for i in sel for b in (False, True)]
    with ThreadPoolExecutor(jobs) as ex:
        res = dict(zip(tasks, ex.map(lambda t: run(*t), tasks)))
    rows, errs = [], {False: ([], []), True: ([], [])}
    for i in sel:
        d = DESIGNS[i]
        cells = [f"{i}", f"{d[0]:.2f}", f"{d[1]:.2f}", f"{d[2]:.2f}", f"{d[3]:.0f}", f"{d[4]:.1f}", f"{d[5] / 1e3:.0f}"]
        for b in (False, True):
            r = res[(i, b)]
            if r is None:
                cells += ["failed", "", "", ""]
                continue
            ed, ef = r[0] / d[4] - 1, r[1] / d[5] - 1
            errs[b][0].append(ed)
            errs[b][1].append(ef)
            cells += [f"{r[0]:.1f}", f"{ed:+.1%}", f"{r[1] / 1e3:.0f}", f"{ef:+.1%}"]
        rows.append("| " + " | ".join(cells) + " |")
        print(rows[-1], flush=True)
    lines = ["# car6's designs against LS-DYNA (`tools/car6_designs.py`)", "",
             "The first 16 designs of the deck owners' Latin-hypercube sample (dbrizard/GSA-car-crash, "
             "LHS/4param/LHS-100), each run as published (xdyna's default: the stiffness-form hourglass of "
             "plastic shells bounded by the modes' plastic capacity; doc/theory.md) and with "
             "`*CONTROL_XDYNA_SHELL` HGBOUND 0 (elastic hourglass springs without limit), "
             "whole runs on one thread. Crush: node 605's least x-displacement (LS-DYNA's dmax); force: the "
             "post's largest x-force (LS-DYNA's fmax). Errors against LS-DYNA's answer for the same design.", "",
             "| design | tbumper (mm) | trailb (mm) | trailf (mm) | yrailf (MPa) | LS-DYNA crush (mm) | "
             "LS-DYNA force (kN) | crush | error | force (kN) | error | crush, HGBOUND 0 | error | force (kN), "
             "HGBOUND 0 | error |", "|" + "---|" * 15] + rows + [""]
    for b, name in ((False, "as published (bounded hourglass, the default)"),
                    (True, "HGBOUND 0 (elastic hourglass springs)")):
        ed, ef = np.array(errs[b][0]), np.array(errs[b][1])
        if len(ed) == 0:
            continue
        lines.append(f"- {name}: crush error mean {ed.mean():+.1%} (from {ed.min():+.1%} to {ed.max():+.1%}; "
                     f"shorter than LS-DYNA's in {int((ed < 0).sum())} of {len(ed)}); force error mean "
                     f"{ef.mean():+.1%} (from {ef.min():+.1%} to {ef.max():+.1%}; higher in {int((ef > 0).sum())} "
                     f"of {len(ef)}).")
    if len(sel) == len(DESIGNS):
        with open(REPORT, "w") as f:
            f.write("\n".join(lines) + "\n")
    print("\n".join(lines[-2:]))
    return 0 if all(r is not None for r in res.values()) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
