#!/usr/bin/python3
"""The crush family (issue 28): thin-walled steel tubes crushed axially at
10 m/s, answered by physics, each with the whole-model single-surface
contact and again with the contact card removed (what the contact adds).

    crush_family.py [--only NAME] [--jobs N] [--per-fold N] [--qm Q] [--dt2ms F]
                    [--istupd 0|1] [--trigger A] [--length L] [--crush C] [--hgbound 0|1]

--per-fold and --qm change the mesh (elements per half-fold, 3) and the
shells' stiffness hourglass coefficient (0.02) for a mesh study; a run
that stops on the way prints its mean force over the crush it reached.
--dt2ms F adds mass scaling (*CONTROL_TIMESTEP DT2MS = -F h / c, h the
element size, c the plate wave speed); --istupd 0 keeps the shells'
thickness (the family sets *CONTROL_SHELL ISTUPD 1: it follows their
strain); --trigger A the square tubes' imperfection amplitude in wall
thicknesses (0.1; 0: the perfect tube); --length and --crush the tube's
length in widths (3) and the crush as a fraction of it (0.6); --hgbound 0
elastic hourglass springs without limit (*CONTROL_XDYNA_SHELL HGBOUND 0;
the default 1 bounds them by the modes' plastic capacity).

Tubes: square (side b, wall t) and circular (diameter D, wall t) on
mid-surfaces, 40-100 mm across, walls 1-3 mm, b/t and D/t 20-60,
length 3 b (3 D), Belytschko-Tsay shells (NIP 5, stiffness hourglass QM
0.02 as the demo, thickness following the strain: *CONTROL_SHELL ISTUPD
1), elastic-perfectly plastic steel (*MAT_024, sigma_0 = 250 MPa, no
hardening), bottom ring clamped, top ring driven down at 10 m/s (a
rigid plate bonded to the end: the top ring held in x, y and rotation), to a crush of 60% of the length (before the
folds stack up: Abramowicz and Jones's effective crushing distance is
about 0.73 of it). Element size a third of Wierzbicki and Abramowicz's
half-fold length (at most b/8). The square tubes carry a trigger: the
first layer of the symmetric folding mode (W&A's: two opposite faces out,
the other two in, over one layer 2H high from the clamped end) as an
initial imperfection of 0.1 t at the faces' middles, nothing at the
corners. Without it the perfect mesh keeps the tube's four-fold symmetry
and folds all four faces out together and then all in (the extensional
mode, 20-40% above the symmetric mode's force, whatever the mesh): the
formula is for the symmetric mode, which real tubes' imperfections pick.

Answers (units N, m):
- square, mean crushing force, Abramowicz & Jones (1984), with the
  effective crushing distance: P_m = 13.06 sigma_0 t^(5/3) b^(1/3);
- square, half-fold length, Wierzbicki & Abramowicz (1983):
  H = 0.983 t^(1/3) b^(2/3);
- circular, mean crushing force, Abramowicz & Jones (1984), the modified
  Alexander (axisymmetric) analysis divided by the effective crushing
  distance: P_m / M_0 = (20.79 sqrt(D/t) + 11.90) / (0.86 - 0.568
  sqrt(t/D)), M_0 = (2 / sqrt 3) sigma_0 t^2 / 4.
The simulated mean force is the drive's work from 5 mm of crush to the end
over that distance (external work in glstat); the simulated half-fold
length from the spacing, in the undeformed length, of the alternating
lobes (radial displacement extrema beyond t) along the middle line of one
face: half of it for a square tube (one face goes out over one layer of
2H and in over the next), the spacing itself for a circular one (its
concertina folds put an outward and an inward lobe in each 2H). The contact's share is how much the mean force drops
without it.

Returns rows for doc/contact-suite.md (contact_suite.py calls it) and
prints them; a tube is within its band if its mean force with contact is
within 15% of the formula (the issue's acceptance; the mesh, the strain
rate and the trigger make a few percent anyway; von Mises plane-strain
hinges are 2/sqrt(3) stronger than the formula's M_0 = sigma_0 t^2 / 4).
"""
import math
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_decks as g  # noqa: E402

XDYNA = os.path.join(ROOT, "bin", "xdyna")
OUT = os.path.join(ROOT, "build", "crush-family")
SIGMA0, E, RHO, V = 250e6, 200e9, 7850.0, 10.0
BAND = 0.15
# elements per half-fold and the hourglass coefficient (--per-fold, --qm:
# a mesh study; the suite's table is at 3 and 0.02)
PER_FOLD, QM = 3.0, 0.02
# mass scaling (--dt2ms F): DT2MS = -F h / c, h the element size and c the
# plate wave speed (about the first step of a square element); 0: none
MS_FRACTION = 0.0
# *CONTROL_SHELL ISTUPD (--istupd 0|1): 1, the shells' thickness follows
# their strain (with 0 a perfectly plastic plane-stress shell keeps its
# thickness while squeezed in its plane: without the contact, where the
# folds pass through each other, one is squeezed to nothing and its step
# with it, and the run stops)
ISTUPD = 1
# the square tubes' trigger (--trigger A): the symmetric folding mode as an
# initial imperfection of amplitude A t (see trigger() and the docstring)
TRIGGER = 0.1
# tube length in widths and crush as a fraction of the length (--length, --crush)
LENGTH, CRUSH = 3.0, 0.6
# *CONTROL_XDYNA_SHELL HGBOUND (--hgbound 0|1): 1 (xdyna's default), the
# hourglass springs bounded by the modes' plastic capacity (doc/theory.md);
# 0 elastic springs
HGBOUND = 1

# (name, shape, b or D, t), m
TUBES = [("square_b40_t2", "square", 0.040, 2.0e-3),
         ("square_b50_t1.5", "square", 0.050, 1.5e-3),
         ("square_b60_t1", "square", 0.060, 1.0e-3),
         ("square_b100_t2.5", "square", 0.100, 2.5e-3),
         ("circular_d50_t1.5", "circular", 0.050, 1.5e-3),
         ("circular_d80_t2", "circular", 0.080, 2.0e-3)]


def fold_length(b, t):
    return 0.983 * t ** (1 / 3) * b ** (2 / 3)


def mean_force(shape, b, t):
    if shape == "square":
        return 13.06 * SIGMA0 * t ** (5 / 3) * b ** (1 / 3)
    m0 = 2.0 / math.sqrt(3.0) * SIGMA0 * t ** 2 / 4.0
    return m0 * (20.79 * math.sqrt(b / t) + 11.90) / (0.86 - 0.568 * math.sqrt(t / b))


def ring(shape, b, n):
    """n points of the tube's cross-section (mid-surface), counter-clockwise;
    for a square, n a multiple of 4, corners included."""
    if shape == "circular":
        return [(0.5 * b * math.cos(2 * math.pi * k / n), 0.5 * b * math.sin(2 * math.pi * k / n)) for k in range(n)]
    m = n // 4
    pts = []
    corners = [(-0.5 * b, -0.5 * b), (0.5 * b, -0.5 * b), (0.5 * b, 0.5 * b), (-0.5 * b, 0.5 * b)]
    for s in range(4):
        (x0, y0), (x1, y1) = corners[s], corners[(s + 1) % 4]
        pts += [(x0 + (x1 - x0) * k / m, y0 + (y1 - y0) * k / m) for k in range(m)]
    return pts


def trigger(x, y, z, b, t):
    """The square tube's initial imperfection: Wierzbicki and Abramowicz's
    symmetric mode (faces x = +-b/2 out where faces y = +-b/2 go in, and the
    other way one fold of 2H higher), amplitude TRIGGER t, zero at the
    corners and at the clamped bottom. Without it the perfect mesh keeps
    the tube's four-fold symmetry and folds all four faces together (the
    extensional mode, stiffer than the symmetric one A&J's formula is for)."""
    hw = 0.5 * b
    on_x, on_y = abs(abs(x) - hw) < 1e-9 * b, abs(abs(y) - hw) < 1e-9 * b
    if on_x == on_y:
        return x, y
    s, sign = (y, 1.0) if on_x else (x, -1.0)
    if z >= 2.0 * fold_length(b, t):
        return x, y
    w = TRIGGER * t * sign * math.cos(math.pi * s / b) * math.sin(math.pi * z / (2.0 * fold_length(b, t)))
    return (x + math.copysign(1.0, x) * w, y) if on_x else (x, y + math.copysign(1.0, y) * w)


def deck(name, shape, b, t, contact):
    h = min(fold_length(b, t) / PER_FOLD, b / 8.0)
    n = max(8, round(math.pi * b / h)) if shape == "circular" else 4 * max(4, math.ceil(b / h))
    L = LENGTH * b
    nz = math.ceil(L / h)
    pts = ring(shape, b, n)
    nodes = {}
    for j in range(nz + 1):
        for k, (x, y) in enumerate(pts):
            z = L * j / nz
            if shape == "square" and TRIGGER > 0:
                x, y = trigger(x, y, z, b, t)
            nodes[1 + k + n * j] = (x, y, z)
    shells = ["*ELEMENT_SHELL"]
    for j in range(nz):
        for k in range(n):
            a, c = 1 + k + n * j, 1 + (k + 1) % n + n * j
            shells.append(f"{1 + k + n * j:8d}{1:8d}{a:8d}{c:8d}{c + n:8d}{a + n:8d}")
    bottom = list(range(1, n + 1))
    top = list(range(1 + n * nz, n + 1 + n * nz))
    # the middle line of the face at y = -b/2 (square), or the line at angle
    # 0 (circular): its radial displacement shows the lobes
    kmid = n // 8 if shape == "square" else 0
    line = [1 + kmid + n * j for j in range(nz + 1)]
    endtim = CRUSH * L / V
    lines = g.common(f"{name}: axial crush at 10 m/s", endtim, endtim / 100)
    if MS_FRACTION > 0:
        c = math.sqrt(E / (RHO * (1 - 0.3 ** 2)))
        i = lines.index("*CONTROL_TIMESTEP")
        lines[i + 1] = g.f10(0.0, 0.9, 0, 0.0, -MS_FRACTION * h / c)
    if ISTUPD:
        lines += ["*CONTROL_SHELL", g.f10(20.0, 0, -1, 1)]
    if not HGBOUND:
        lines += ["*CONTROL_XDYNA_SHELL", g.f10(0)]
    lines += ["*CONTROL_HOURGLASS", g.f10(4, QM),
              "*SECTION_SHELL", g.f10(2, 2, 1.0, 5), g.f10(t, t, t, t),
              "*MAT_PIECEWISE_LINEAR_PLASTICITY", g.f10(1, RHO, E, 0.3, SIGMA0, 0.0)]
    lines += g.part(1, 1, "tube")[:2] + [g.f10(1, 2, 1)]
    lines += g.node_set(1, bottom) + ["*BOUNDARY_SPC_SET", g.f10(1, 0, 1, 1, 1, 1, 1, 1)]
    # the plate bonded to the top: the ring moves down, held in x and y and
    # in rotation (free, the ring flared out and the tube everted over itself)
    lines += g.node_set(2, top) + ["*BOUNDARY_SPC_SET", g.f10(2, 0, 1, 1, 0, 1, 1, 1), "*DEFINE_CURVE", g.f10(7), f"{0.0:20.8e}{-V:20.8e}", f"{1.0:20.8e}{-V:20.8e}",
                                   "*BOUNDARY_PRESCRIBED_MOTION_SET", g.f10(2, 3, 0, 7, 1.0)]
    if contact:
        lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", g.f10(0), "", ""]
    lines += g.node_set(3, line) + ["*DATABASE_NODOUT", g.f10(endtim / 100), "*DATABASE_HISTORY_NODE_SET", g.f10(3)]
    lines += g.node_cards(nodes) + shells
    path = os.path.join(OUT, name + ("" if contact else "_nocontact"), "deck.k")
    g.write(path, lines)
    return path, h, kmid, n


def run_one(job):
    name, shape, b, t, contact = job
    path, h, kmid, n = deck(name, shape, b, t, contact)
    d = os.path.dirname(path)
    t0 = time.time()
    p = subprocess.run([XDYNA, "i=" + path, "outdir=" + d], capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1", XDYNA_H5PLOT="0"))
    res = {"name": name, "contact": contact, "rc": p.returncode, "wall": time.time() - t0, "h": h}
    if p.returncode != 0:
        # a run stopped on the way: the mean force over the crush it reached
        try:
            with h5py.File(os.path.join(d, "thist.h5"), "r") as f:
                tt, w = f["glstat/time"][:], f["glstat/external_work"][:]
            t5 = 0.005 / V
            if tt[-1] > 2 * t5:
                res["partial"] = (float((w[-1] - np.interp(t5, tt, w)) / (V * (tt[-1] - t5))), float(tt[-1] * V))
        except (OSError, KeyError):
            pass
        return res
    with h5py.File(os.path.join(d, "thist.h5"), "r") as f:
        tt, w = f["glstat/time"][:], f["glstat/external_work"][:]
        slide = f["glstat/sliding_interface_energy"][:] if "sliding_interface_energy" in f["glstat"] else np.zeros(1)
        x, y, z = f["nodout/x_coordinate"][:], f["nodout/y_coordinate"][:], f["nodout/z_coordinate"][:]
    t5 = 0.005 / V
    res["force"] = float((w[-1] - np.interp(t5, tt, w)) / (V * (tt[-1] - t5)))
    res["slide_min"] = float(slide.min())
    res["slide_end"] = float(slide[-1])
    res["work"] = float(w[-1])
    # radial displacement along the middle line, ordered by initial height
    r0 = np.hypot(x[0], y[0]) if shape == "circular" else -y[0]
    r = np.hypot(x[-1], y[-1]) if shape == "circular" else -y[-1]
    order = np.argsort(z[0])
    u, z0 = (r - r0)[order], z[0][order]
    ext = [i for i in range(1, len(u) - 1) if abs(u[i]) > t and
           ((u[i] > u[i - 1] and u[i] >= u[i + 1]) or (u[i] < u[i - 1] and u[i] <= u[i + 1]))]
    alt = [(a, c) for a, c in zip(ext, ext[1:]) if np.sign(u[a]) != np.sign(u[c])]
    res["lobes"] = len(ext)
    # one layer of a square tube's symmetric mode is 2H high and takes a
    # face out (the next layer in): its alternating lobes lie 2H apart; a
    # circular tube's concertina puts both in each 2H
    # concertina folds (Alexander's) with every lobe outward: those lie 2H apart
    div = 2.0 if shape == "square" else 1.0
    if not alt:
        alt, div = list(zip(ext, ext[1:])), 2.0 * div
    res["fold"] = float(np.mean([z0[c] - z0[a] for a, c in alt])) / div if alt else float("nan")
    return res


def run_family(jobs=2, only=None):
    todo = [(nm, sh, b, t, c) for nm, sh, b, t in TUBES for c in (True, False) if not only or only in nm]
    with ThreadPoolExecutor(max_workers=jobs) as ex:
        res = list(ex.map(run_one, todo))
    rows = []
    for nm, sh, b, t in TUBES:
        on = [r for r in res if r["name"] == nm and r["contact"]]
        off = [r for r in res if r["name"] == nm and not r["contact"]]
        if not on:
            continue
        on, off = on[0], off[0]
        pm = mean_force(sh, b, t)
        row = {"name": nm, "shape": sh, "b": b, "t": t, "h": on["h"], "pm": pm, "rc": (on["rc"], off["rc"]),
               "partial_on": on.get("partial"), "partial_off": off.get("partial")}
        if on["rc"] == 0 and off["rc"] == 0:
            row.update(force=on["force"], force_off=off["force"], err=on["force"] / pm - 1,
                       err_off=off["force"] / pm - 1, fold=on["fold"], lobes=on["lobes"],
                       slide_min=on["slide_min"], slide_end=on["slide_end"], work=on["work"], wall=on["wall"] + off["wall"])
            if sh == "square":
                row["fold_aj"] = fold_length(b, t)
        row["ok"] = on["rc"] == 0 and off["rc"] == 0 and abs(row.get("err", 1.0)) <= BAND
        rows.append(row)
    return rows


def markdown(rows):
    out = ["## Crush family (issue 28)", "",
           "Written by `make contact-suite` (tools/crush_family.py, whose docstring gives the decks and the "
           "formulas). Steel tubes, elastic-perfectly plastic (sigma_0 250 MPa), "
           + ("thickness following the strain (ISTUPD 1)" if ISTUPD else "thickness kept (ISTUPD 0)") + ", crushed axially at 10 m/s to 60% of their length; mean force from 5 mm of crush on. The "
           "square tubes start from a trigger, the symmetric folding mode's first layer as an imperfection of "
           f"{TRIGGER:g} t (without it the perfect tube folds in the stiffer extensional mode: doc/theory.md). Band: the "
           f"mean force with contact within {BAND:.0%} of Abramowicz and Jones's. Half-fold: from the spacing of "
           "the alternating lobes along one face's middle line (square tubes: against Wierzbicki and Abramowicz's "
           "H = 0.983 t^(1/3) b^(2/3)). Sliding energy, lowest over the run and at its end: of the drive's work (a "
           "frictionless contact must not do net positive work; what it ends with is what its springs hold and "
           "the round-off of the trapezoid rule).", "",
           "| tube | b/t | element (mm) | A&J P_m (kN) | with contact (kN) | error | without contact (kN) | error "
           "| contact adds | half-fold (mm) | W&A H (mm) | sliding energy: lowest, end | result |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "force" not in r:
            got = []
            for tag, rc, pr in (("with", r["rc"][0], r.get("partial_on")), ("without", r["rc"][1], r.get("partial_off"))):
                got.append(f"exit {rc}" + (f", {pr[0] / 1e3:.1f} kN to {pr[1] * 1e3:.0f} mm" if rc and pr else ""))
            out.append(f"| {r['name']} | {r['b'] / r['t']:.0f} | {r['h'] * 1e3:.1f} | {r['pm'] / 1e3:.1f} | {got[0]} "
                       f"| | {got[1]} | | | | | | FAIL |")
            continue
        fa = f"{r['fold_aj'] * 1e3:.1f}" if "fold_aj" in r else "-"
        out.append(f"| {r['name']} | {r['b'] / r['t']:.0f} | {r['h'] * 1e3:.1f} | {r['pm'] / 1e3:.1f} | "
                   f"{r['force'] / 1e3:.1f} | {r['err']:+.1%} | {r['force_off'] / 1e3:.1f} | {r['err_off']:+.1%} | "
                   f"{r['force'] / r['force_off'] - 1:+.1%} | {r['fold'] * 1e3:.1f} ({r['lobes']} lobes) | {fa} | "
                   f"{r['slide_min'] / r['work']:+.1e}, {r['slide_end'] / r['work']:+.1e} | "
                   f"{'pass' if r['ok'] else 'outside the band'} |")
    n = sum(1 for r in rows if r["ok"])
    out += ["", f"{n} of {len(rows)} tubes within {BAND:.0%} of the formula.", ""]
    return out


def main(argv):
    global PER_FOLD, QM, OUT, MS_FRACTION, ISTUPD, LENGTH, CRUSH, TRIGGER, HGBOUND
    jobs = int(argv[argv.index("--jobs") + 1]) if "--jobs" in argv else 2
    only = argv[argv.index("--only") + 1] if "--only" in argv else None
    opts = {"--per-fold": ("PER_FOLD", float), "--qm": ("QM", float), "--dt2ms": ("MS_FRACTION", float),
            "--istupd": ("ISTUPD", int), "--length": ("LENGTH", float), "--trigger": ("TRIGGER", float),
            "--crush": ("CRUSH", float), "--hgbound": ("HGBOUND", int)}
    for flag, (name, kind) in opts.items():
        if flag in argv:
            globals()[name] = kind(argv[argv.index(flag) + 1])
    if (PER_FOLD, QM, MS_FRACTION, ISTUPD, LENGTH, CRUSH, TRIGGER, HGBOUND) != (3.0, 0.02, 0.0, 1, 3.0, 0.6, 0.1, 1):
        OUT = OUT + f"-h{PER_FOLD:g}-qm{QM:g}" + (f"-ms{MS_FRACTION:g}" if MS_FRACTION else "") + \
            f"-istupd{ISTUPD}-trig{TRIGGER:g}" + (f"-L{LENGTH:g}-c{CRUSH:g}" if (LENGTH, CRUSH) != (3.0, 0.6) else "") + \
            ("" if HGBOUND else "-elastic-hg")
    rows = run_family(jobs, only)
    for r in rows:
        for tag, pr in (("with", r.get("partial_on")), ("without", r.get("partial_off"))):
            if pr:
                print(f"{r['name']} {tag} contact stopped at {pr[1] * 1e3:.1f} mm of crush: mean force to there "
                      f"{pr[0] / 1e3:.1f} kN ({pr[0] / r['pm'] - 1:+.1%} of the formula)")
    print("\n".join(markdown(rows)))
    return 0 if all(r["ok"] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
