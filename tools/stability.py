#!/usr/bin/python3
"""make stability: stiff and extreme cases (issues 9 and 18). Each case is a
deck written here into build/stability/, run with a time limit. A case that
LS-DYNA would run must finish with its energy ratio inside a stated band
and no NaN in any output: a stop is a failure there. Only a case that is
physically meant to fail (marked "stop") passes by stopping, with exit 2
and a diagnostic naming the cause. A hang (the time limit) or NaN written
silently fails any case.

Writes the summary into doc/verification.md (after the marker line
'<!-- stability -->', which `make verify` keeps) and prints it. Exit 1 if
a case fails.
"""
import os
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
import gen_decks as g  # noqa: E402

XDYNA = os.path.join(ROOT, "bin", "xdyna")
OUT = os.path.join(ROOT, "build", "stability")
MARK = "<!-- stability -->"
LIMIT = 300  # seconds: a case still running then has hung


def two_bars(name, slsfac=None, rho2=7850.0, title="two elastic bars through contact"):
    """Two 100 mm steel bars (20 hexahedra each) meeting head-on at 5 m/s
    each through whole-model contact; the second bar's density rho2."""
    L, a, gap, v0, n = 0.1, 0.01, 1.0e-4, 5.0, 20
    A = g.block_mesh(n, 1, 1, L, a, a)
    B = g.block_mesh(n, 1, 1, L, a, a, origin=(L + gap, 0.0, 0.0), nid0=1001, eid0=1001)
    lines = g.common(title, 1.2e-4, 1.0e-6)
    lines += ["*MAT_ELASTIC", g.f10(1, 7850.0, 200e9, 0.0), "*MAT_ELASTIC", g.f10(2, rho2, 200e9, 0.0)]
    lines += g.part(1, 1, "left bar") + g.part(2, 2, "right bar")
    lines += g.node_set(1, sorted(A[0])) + g.node_set(2, sorted(B[0]))
    lines += ["*INITIAL_VELOCITY", g.f10(1), g.f10(v0, 0.0, 0.0), "*INITIAL_VELOCITY", g.f10(2), g.f10(-v0, 0.0, 0.0)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", g.f10(0), "", ""]
    if slsfac:
        lines += ["*CONTROL_CONTACT", g.f10(slsfac)]
    lines += g.node_cards({**A[0], **B[0]}) + g.solid_cards(A[1], 1) + g.solid_cards(B[1], 2)
    return lines


def plate_impact(name, v, t, endtim):
    """A 20 mm steel cube (2 x 2 x 2 hexahedra) at v onto a 0.1 m square
    plate of 20 x 20 *MAT_024 shells, thickness t, clamped round its edge;
    whole-model contact."""
    blk, hexes = g.block_mesh(2, 2, 2, 0.02, 0.02, 0.02, origin=(0.04, 0.04, 0.002))
    n, a = 20, 0.1
    pid = lambda i, j: 5001 + i + (n + 1) * j
    lines = g.common(name, endtim, endtim / 100)
    lines += ["*SECTION_SHELL", g.f10(2, 2, 1.0, 5), g.f10(t, t, t, t)]
    lines += ["*MAT_ELASTIC", g.f10(1, 7850.0, 200e9, 0.3)]
    lines += ["*MAT_PIECEWISE_LINEAR_PLASTICITY", g.f10(2, 7850.0, 210e9, 0.3, 250e6, 1e9)]
    lines += g.part(1, 1, "cube") + ["*PART", "plate", g.f10(2, 2, 2)]
    lines += g.node_set(1, sorted(blk))
    lines += ["*INITIAL_VELOCITY", g.f10(1), g.f10(0.0, 0.0, -v)]
    edge = [pid(i, j) for j in range(n + 1) for i in range(n + 1) if i in (0, n) or j in (0, n)]
    lines += g.node_set(2, edge) + ["*BOUNDARY_SPC_SET", g.f10(2, 0, 1, 1, 1, 1, 1, 1)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", g.f10(0), "", ""]
    lines += g.node_cards(blk) + g.solid_cards(hexes, 1)
    lines += ["*NODE"] + [f"{pid(i, j):8d}{a * i / n:16.9e}{a * j / n:16.9e}{0.0:16.9e}{0:8d}{0:8d}"
                          for j in range(n + 1) for i in range(n + 1)]
    lines += ["*ELEMENT_SHELL"] + [f"{5001 + i + n * j:8d}{2:8d}{pid(i, j):8d}{pid(i + 1, j):8d}"
                                   f"{pid(i + 1, j + 1):8d}{pid(i, j + 1):8d}" for j in range(n) for i in range(n)]
    return lines


def block_on_wall(name, nu, rigid=False, v=10.0, endtim=3.0e-4, ihq=0):
    """A 50 mm block (4 x 4 x 4) at v onto a planar rigid wall; elastic
    with Poisson's ratio nu, or *MAT_RIGID; hourglass form ihq (0: the
    default viscous one)."""
    nodes, hexes = g.block_mesh(4, 4, 4, 0.05, 0.05, 0.05, origin=(0.0, 0.0, 1.0e-4))
    lines = g.common(name, endtim, endtim / 100)
    if ihq:
        lines += ["*CONTROL_HOURGLASS", g.f10(ihq, 0.05)]
    if rigid:
        lines = [x if x != g.f10(0.0, 0.9) else g.f10(1.0e-6, 0.9) for x in lines]
        lines += ["*MAT_RIGID", g.f10(1, 7850.0, 200e9, 0.3)]
    else:
        lines += ["*MAT_ELASTIC", g.f10(1, 1000.0, 10e6, nu)]
    lines += g.part(1, 1, "block")
    lines += ["*RIGIDWALL_PLANAR", g.f10(0), g.f10(0.0, 0.0, 0.0, 0.0, 0.0, 1.0)]
    lines += ["*INITIAL_VELOCITY", g.f10(0), g.f10(0.0, 0.0, -v)]
    lines += g.node_cards(nodes) + g.solid_cards(hexes, 1)
    return lines


def graded_bar(name):
    """A 100 mm steel bar of 20 hexahedra, one of them 100 times shorter
    than the rest (0.05 mm next to 5 mm), at 10 m/s onto a planar rigid wall."""
    a, v = 0.005, 10.0
    xs = [0.0, 5.0e-5] + [5.0e-5 + 0.005 * k for k in range(1, 21)]
    nodes, hexes = {}, []
    nid = lambda i, j, k: 1 + i + len(xs) * (j + 2 * k)
    for k in range(2):
        for j in range(2):
            for i, x in enumerate(xs):
                nodes[nid(i, j, k)] = (x + 1.0e-4, a * j, a * k)
    for i in range(len(xs) - 1):
        hexes.append((i + 1, nid(i, 0, 0), nid(i + 1, 0, 0), nid(i + 1, 1, 0), nid(i, 1, 0),
                      nid(i, 0, 1), nid(i + 1, 0, 1), nid(i + 1, 1, 1), nid(i, 1, 1)))
    lines = g.common(name, 1.0e-4, 1.0e-6)
    lines += ["*MAT_ELASTIC", g.f10(1, 7850.0, 200e9, 0.0)] + g.part(1, 1, "bar")
    lines += ["*RIGIDWALL_PLANAR", g.f10(0), g.f10(0.0, 0.0, 0.0, 1.0, 0.0, 0.0)]
    lines += ["*INITIAL_VELOCITY", g.f10(0), g.f10(-v, 0.0, 0.0)]
    lines += g.node_cards(nodes) + g.solid_cards(hexes, 1)
    return lines


def overlapping_blocks(name):
    """Two 50 mm elastic blocks (3 x 3 x 3) at rest, the upper one sunk
    2 mm into the lower one at t = 0; whole-model contact."""
    lo = g.block_mesh(3, 3, 3, 0.05, 0.05, 0.05)
    up = g.block_mesh(3, 3, 3, 0.05, 0.05, 0.05, origin=(0.01, 0.01, 0.048), nid0=1001, eid0=1001)
    lines = g.common(name, 2.0e-3, 2.0e-5)
    lines += ["*MAT_ELASTIC", g.f10(1, 7850.0, 200e9, 0.3)]
    lines += g.part(1, 1, "lower block") + g.part(2, 1, "upper block")
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", g.f10(0), "", ""]
    lines += g.node_cards({**lo[0], **up[0]}) + g.solid_cards(lo[1], 1) + g.solid_cards(up[1], 2)
    return lines


# name, what it probes, deck, energy-ratio band[, "stop" for a case meant to fail]
CASES = [
    ("penalty_x100", "contact penalty scale x100 (SLSFAC 10): the spring is 100 times stiffer than the default",
     lambda n: two_bars(n, slsfac=10.0), 0.02),
    ("penalty_x1000", "contact penalty scale x1000 (SLSFAC 100)", lambda n: two_bars(n, slsfac=100.0), 0.02),
    ("mass_ratio_1e4", "mass ratio 1e4 across a contact: a steel bar strikes a bar 10,000 times denser",
     lambda n: two_bars(n, rho2=7850.0e4), 0.02),
    ("impact_1km_s", "1 km/s impact of a steel cube on a 1 mm steel plate",
     lambda n: plate_impact(n, 1000.0, 1.0e-3, 1.0e-4), 0.10),
    ("shell_0.1mm", "0.1 mm shells: a cube at 20 m/s on a 0.1 mm steel plate",
     lambda n: plate_impact(n, 20.0, 1.0e-4, 1.0e-3), 0.05),
    ("nu_0.4999", "nearly incompressible solid (nu = 0.4999) on a rigid wall, default viscous hourglass (QM 0.1)",
     lambda n: block_on_wall(n, 0.4999), 0.02),
    ("nu_0.4999_ihq4", "the same with the stiffness hourglass form the diagnostic advises (IHQ 4, QM 0.05)",
     lambda n: block_on_wall(n, 0.4999, ihq=4), 0.02),
    ("tiny_element", "an element 100 times shorter than its neighbours (bar on a rigid wall)", graded_bar, 0.02),
    ("rigid_on_wall", "a rigid body striking a planar rigid wall", lambda n: block_on_wall(n, 0.3, rigid=True),
     0.02),
    ("initial_penetration", "two blocks overlapping by 2 mm at t = 0 under contact", overlapping_blocks, 0.02),
]


def has_nan(path):
    """Any NaN or infinity in the numeric datasets of an HDF5 file."""
    bad = []
    if not os.path.exists(path):
        return False
    with h5py.File(path, "r") as f:
        def visit(k, v):
            if isinstance(v, h5py.Dataset) and v.dtype.kind == "f" and not np.all(np.isfinite(v[()])):
                bad.append(k)
        f.visititems(visit)
    return bool(bad)


def run_case(name, what, build, band, expect="run"):
    deck = os.path.join(OUT, name + ".k")
    g.write(deck, build(name))
    out = os.path.join(OUT, name)
    t0 = time.time()
    try:
        p = subprocess.run([XDYNA, "i=" + deck, "outdir=" + out], capture_output=True, text=True, timeout=LIMIT,
                           env={**os.environ, "OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS", "1")})
        rc, err = p.returncode, p.stderr.strip().splitlines()
    except subprocess.TimeoutExpired:
        return dict(name=name, what=what, ok=False, outcome=f"hung (still running after {LIMIT} s)", wall=LIMIT)
    wall = time.time() - t0
    nan = has_nan(os.path.join(out, "thist.h5")) or has_nan(os.path.join(out, "d3plot.h5"))
    info = dict(name=name, what=what, wall=wall)
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        gl = {k: f["glstat"][k][:] for k in f["glstat"]}
    ratio = gl["energy_ratio"]
    dt = gl["time_step"]
    finite = ratio[np.isfinite(ratio)]
    dev = float(np.max(np.abs(finite - 1.0))) if len(finite) else float("nan")
    log = open(os.path.join(out, "d3hsp")).read()
    contact_step = "contact sets the time step" in log
    cycles = log.split("cycles ...............................")[-1].split()[0] if "cycles ......" in log else "?"
    if rc == 0:
        ok = not nan and dev <= band
        outcome = (f"finished: {cycles} cycles, energy ratio within {dev:.1e} of 1 (band {band:g}), "
                   f"step {dt.min():.3g} s (first {dt[0]:.3g})"
                   + ("; the contact springs set the step (warned in d3hsp)" if contact_step else ""))
        if nan:
            outcome += "; NaN in an output"
    elif rc == 2:
        # a stop must name its cause: the message says what went wrong and
        # where (the element, node or part) and at what time; and it passes
        # only where the case is meant to fail
        ok = expect == "stop" and not nan and len(err) > 0 and "at time" in err[-1] and ("node" in err[-1] or "element" in err[-1]
                                                                    or "solid" in err[-1] or "shell" in err[-1])
        outcome = "stopped, exit 2: " + (err[-1] if err else "no message")
    else:
        ok = False
        outcome = f"exit {rc}: " + (err[-1] if err else "")
    info.update(ok=ok, outcome=outcome)
    return info


def main():
    os.makedirs(OUT, exist_ok=True)
    rows = [run_case(*c) for c in CASES]
    lines = [MARK, "", "## Stability on stiff and extreme cases (`make stability`)", "",
             "Each case must finish with its energy ratio inside the band and no NaN in thist.h5 or "
             "d3plot.h5: a stop fails it, as LS-DYNA would run every one of them (a case physically meant "
             "to fail would pass by stopping with exit 2 and a message naming the cause; none is so marked "
             f"now). A case still running after {LIMIT} s has hung. Decks: `tools/stability.py` writes them "
             "into `build/stability/`.", "",
             "| case | what it probes | outcome | pass | wall (s) |", "|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['name']} | {r['what']} | {r['outcome']} | {'yes' if r['ok'] else '**no**'} | "
                     f"{r['wall']:.1f} |")
        print(("PASS " if r["ok"] else "FAIL ") + r["name"] + ": " + r["outcome"], flush=True)
    nfail = sum(not r["ok"] for r in rows)
    lines += ["", f"{len(rows) - nfail} cases passed, {nfail} failed."]
    doc = os.path.join(ROOT, "doc", "verification.md")
    text = open(doc).read() if os.path.exists(doc) else "# Verification\n"
    head = text.split(MARK)[0].rstrip("\n")
    with open(doc, "w") as f:
        f.write(head + "\n\n" + "\n".join(lines) + "\n")
    print(f"stability: {len(rows) - nfail} passed, {nfail} failed; summary in doc/verification.md")
    return 1 if nfail else 0


if __name__ == "__main__":
    sys.exit(main())
