#!/usr/bin/python3
"""make contact-suite: the contact torture suite (issue 16).

    contact_suite.py [--fast] [--only SUBSTRING [--merge]] [--jobs N] [--no-report] [--list] [--report-only]
                     [--penmax X]

(--only runs the matching cases; with --merge their results replace those
of the last full run and the report is written from both.)

Generates, as a product of what a user varies, small decks whose contact
has an answer, runs each one and holds it to that answer:

- pairs: solid on solid (two elastic bars head-on), shell on shell (two
  plates face to face), shell on a solid face (a plate onto a rigid block),
  shell edge on a face (a plate edge-first onto a fixed rigid block),
  coplanar shell edges (two plates in one plane, edge to edge), shell edge
  across shell edge (two crossed plates), solid corner on a face (a cube
  corner-first onto a fixed rigid block), self-contact of a folding strip;
- alignment: node on node, half an element offset, a random offset,
  rotated 15-45 degrees about each axis; mesh ratios 1:1, 1:3, 3:1; one to
  four elements across;
- speeds 1, 10, 100, 1000 m/s; shell thickness 0.1 to 5 mm; penalty and
  Lagrangian projection; single surface, surface to surface, nodes to
  surface.

Every case is held to: exit 0; the energy ratio within its band; max
4u/delta <= 1 (the search bound, from d3hsp); no pass-through and the
worst overlap (the independent penetration checker, tools/penetration.py)
within its bound; and, where a closed form exists, the rebound velocities
(1-D elastic impact: equal bars, equal plates, a bar or membrane on a
fixed wall, a plate on a free rigid block), else a bounce (the bodies
separate). Writes doc/contact-suite.md (every case: its answer, its
error, pass/fail, wall time) unless --fast or --no-report; exit 1 if a
case fails. --fast runs the subset that `make check` runs. --penmax X
writes PENMAX X on each contact's optional card B (a study: LS-DYNA's
default is 0.4; with it the report is not written).
"""
import json
import math
import os
import random
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# the runs' states also in d3plot.h5, which this tool reads (the d3plot
# family in LS-DYNA's layout is written as well)
os.environ.setdefault("XDYNA_H5PLOT", "1")
sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_decks as g  # noqa: E402
import penetration  # noqa: E402
import crush_family  # noqa: E402

XDYNA = os.path.join(ROOT, "bin", "xdyna")
OUT = os.path.join(ROOT, "build", "contact-suite")
REPORT = os.path.join(ROOT, "doc", "contact-suite.md")
LIMIT = 120  # seconds: a case still running then has hung

RHO, E = 7850.0, 200e9
C = math.sqrt(E / RHO)  # bar (and nu = 0 membrane) wave speed, m/s
K_BULK = E / 3.0        # bulk modulus at nu = 0, the penalty's modulus


def spring_time(mass, h, area, slsfac=0.1):
    """Half period of a body of `mass` on the penalty springs of `area` of
    shell segments of size h (stiffness per area SLSFAC K / diagonal): the
    contact lasts about this long when the spring, not the body's wave,
    sets it."""
    kpa = slsfac * K_BULK / (h * math.sqrt(2.0))
    return math.pi * math.sqrt(mass / (kpa * area))


# ---------------------------------------------------------------- meshes

class Body:
    """Nodes (n, 3) and elements (hex: 8 node indices, shell: 4) of one
    part, local numbering."""

    def __init__(self, x, elems, kind):
        self.x = np.asarray(x, dtype=float)
        self.e = np.asarray(elems, dtype=int)
        self.kind = kind  # "hex" or "shell"

    def moved(self, R=None, about=None, shift=(0.0, 0.0, 0.0)):
        x = self.x.copy()
        if R is not None:
            c = self.x.mean(0) if about is None else np.asarray(about, float)
            x = (x - c) @ np.asarray(R).T + c
        return Body(x + np.asarray(shift, float), self.e, self.kind)


def grid(v):
    return np.asarray(v, dtype=float)


def hex_block(xs, ys, zs):
    """Hexahedra on the grid xs x ys x zs (coordinate lists)."""
    nx, ny, nz = len(xs), len(ys), len(zs)
    X = np.array([(x, y, z) for z in zs for y in ys for x in xs])

    def n(i, j, k):
        return i + nx * (j + ny * k)
    E_ = [(n(i, j, k), n(i + 1, j, k), n(i + 1, j + 1, k), n(i, j + 1, k),
           n(i, j, k + 1), n(i + 1, j, k + 1), n(i + 1, j + 1, k + 1), n(i, j + 1, k + 1))
          for k in range(nz - 1) for j in range(ny - 1) for i in range(nx - 1)]
    return Body(X, E_, "hex")


def shell_grid(us, vs, place):
    """Quadrilaterals on the grid us x vs, placed in 3-D by place(u, v)."""
    nu = len(us)
    X = np.array([place(u, v) for v in vs for u in us])
    E_ = [(i + nu * j, i + 1 + nu * j, i + 1 + nu * (j + 1), i + nu * (j + 1))
          for j in range(len(vs) - 1) for i in range(nu - 1)]
    return Body(X, E_, "shell")


def lin(a, b, n):
    return list(np.linspace(a, b, n + 1))


def shifted(a, b, n):
    """n elements from a to b whose inner nodes sit half an element off
    lin(a, b, n): half-size end elements (n + 1 elements)."""
    h = (b - a) / n
    return [a] + [a + h * (i + 0.5) for i in range(n)] + [b]


def jittered(a, b, n, rng):
    h = (b - a) / n
    return [a] + [a + h * (i + rng.uniform(-0.3, 0.3)) for i in range(1, n)] + [b]


def rot(axis, deg):
    t = math.radians(deg)
    c, s = math.cos(t), math.sin(t)
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


# ----------------------------------------------------------------- decks

def deck(case, bodies, parts, v0, endtim, contact, fixed_rigid=(), free_rigid=(), spc=None):
    """Deck lines: bodies[i] is part i + 1 with material parts[i] ('el',
    'rigid_fixed' or 'rigid_free') and section ('solid' or a shell
    thickness); v0[i] its initial velocity; contact: (kind, lagrange)."""
    ctype, lagrange = contact
    lines = g.common(case["name"], endtim, endtim / 100)
    # histories often enough to see the bounce; 25 states for the checker
    lines[lines.index("*DATABASE_MATSUM") + 1] = g.f10(endtim / 400)
    lines += ["*DATABASE_BINARY_D3PLOT", g.f10(endtim / 25)]
    lines += ["*MAT_ELASTIC", g.f10(1, RHO, E, 0.0)]
    lines += ["*MAT_RIGID", g.f10(2, RHO, E, 0.3), g.f10(1.0, 7, 7)]
    lines += ["*MAT_RIGID", g.f10(3, RHO, E, 0.3), g.f10(0.0, 0, 0)]
    # the shells take the stiffness hourglass form (IHQ 4, QM 0.1): the
    # cases' answers are elastic rebounds, and LS-DYNA's default viscous
    # form (IHQ 1) damps the plates' ringing that the impact sets off
    # (edge on face: 7-25% of the rebound), which is the element's doing,
    # not the contact's
    if any(sec != "solid" for _, sec in parts):
        lines += ["*HOURGLASS", g.f10(1, 4, 0.1)]
    nid, eid, allnodes = 0, 0, []
    for i, (b, (mat, sec)) in enumerate(zip(bodies, parts)):
        pid = i + 1
        mid = {"el": 1, "rigid_fixed": 2, "rigid_free": 3}[mat]
        if sec == "solid":
            lines += ["*SECTION_SOLID", g.f10(10 + pid, 1)]
        else:
            lines += ["*SECTION_SHELL", g.f10(10 + pid, 2, 1.0, 3), g.f10(sec, sec, sec, sec)]
        lines += ["*PART", f"body {pid}", g.f10(pid, 10 + pid, mid, 0, 0 if sec == "solid" else 1)]
        ids = list(range(nid + 1, nid + 1 + len(b.x)))
        lines += g.node_set(pid, ids)
        if any(v != 0.0 for v in v0[i]):
            lines += ["*INITIAL_VELOCITY", g.f10(pid), g.f10(*[float(v) for v in v0[i]])]
        allnodes.append((ids, b))
        nid += len(b.x) + 1000 - (len(b.x) % 1000)
    if spc:
        for pid, dofs in spc:
            lines += ["*BOUNDARY_SPC_SET", g.f10(pid, 0, *dofs)]
    if ctype == "single":
        lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", g.f10(0), "", ""]
    elif ctype == "general":
        lines += ["*CONTACT_AUTOMATIC_GENERAL", g.f10(0), "", ""]
    elif ctype == "s2s":
        lines += ["*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", g.f10(1, 2, 3, 3), "", ""]
    else:
        lines += ["*CONTACT_AUTOMATIC_NODES_TO_SURFACE", g.f10(1, 2, 4, 3), "", ""]
    if PENMAX is not None:
        # (optional card A blank, card B PENMAX)
        lines += ["", g.f10(PENMAX)]
    # SLSFAC: 1 for solid pairs (the interface spring about as stiff as the
    # elements: a stiff, short contact, as the aligned-bar acceptance asks);
    # LS-DYNA's default 0.1 where a shell is in contact (a shell segment's
    # spring K A / diagonal does not fall with the thickness while its mass
    # does: at SLSFAC 1 a 1 mm shell's contact oscillates at omega dt = 1.3,
    # resolved in two steps, and its rebound is off by 50%)
    # SSTHK 1 (card 2): the shells' own thickness in single-surface
    # contacts. Each case's answer (when the bodies meet, the closed-form
    # rebound) is for the thickness in its name; LS-DYNA's default limit of
    # 40% of the shortest edge (SSTHK 0) would make a 5 mm shell on 5 mm
    # elements a 2 mm one and the bodies meet after the case's end. The limit
    # has its own test (make check, test_contact_surface_log).
    lines += ["*CONTROL_CONTACT", g.f10(case.get("slsfac", 1.0 if all(p[1] == "solid" for p in parts) else 0.1)),
              g.f10(0, 0, 0, 0, 0, 1)]
    # xdyna's knobs (SEARCH NSRCH MNL TRACK; the accuracy study sets them)
    knobs = list(case.get("xc", (0, 0, 0, 0))) + [0, 2 if lagrange else 0]
    if any(knobs):
        lines += ["*CONTROL_XDYNA_CONTACT", g.f10(*knobs)]
    lines += ["*NODE"]
    for ids, b in allnodes:
        lines += [f"{n:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for n, (x, y, z) in zip(ids, b.x)]
    for i, (ids, b) in enumerate(allnodes):
        pid = i + 1
        if b.kind == "hex":
            lines += ["*ELEMENT_SOLID"]
            for e in b.e:
                eid += 1
                lines.append(f"{eid:8d}{pid:8d}" + "".join(f"{ids[k]:8d}" for k in e))
        else:
            lines += ["*ELEMENT_SHELL"]
            for e in b.e:
                eid += 1
                lines.append(f"{eid:8d}{pid:8d}" + "".join(f"{ids[k]:8d}" for k in e))
    return lines


# ---------------------------------------------------------------- families
#
# Each builder returns (lines, answer): answer names the closed form the
# case is held to ('rebound' with the expected end velocities of parts
# along an axis, or 'bounce'), the overlap bound and the energy band.

def bars(c):
    """Two equal elastic bars (nu = 0) head-on at +-v: the 1-D answer is
    full reversal, contact for 2L/c. k elements across, n along."""
    a, k, n, gap = 0.01, c["k"], c["n"], 2.0e-5
    h = a / k
    L = n * h
    kb = {"1:1": k, "1:3": 3 * k, "3:1": max(1, k // 3) if k >= 3 else k}[c["ratio"]]
    A = hex_block(lin(0, L, n), lin(0, a, k), lin(0, a, k))
    rng = random.Random(c["seed"])
    if c["align"] == "node":
        ys = lin(0, a, kb)
    elif c["align"] == "half":
        ys = shifted(0, a, kb)
    else:
        ys = jittered(0, a, kb, rng)
    nb = n  # the same elements along: a mesh ratio across only (the 1-D error stays that of n)
    B = hex_block(lin(L + gap, 2 * L + gap, nb), ys, ys if c["align"] != "rand" else jittered(0, a, kb, rng))
    if c.get("rot"):
        B = B.moved(rot(c["rot"][0], c["rot"][1]), about=(L + gap, a / 2, a / 2))
        # turned about its face's centre, part of the face would lie inside
        # the other bar: moved back so that its nearest point is the gap away
        B = B.moved(shift=(L + gap - B.x[:, 0].min(), 0, 0))
    v = c["v"]
    T = gap / (2 * v) + 2 * L / C
    if c.get("rot"):
        T += 3 * a / v  # an oblique edge first: the bars turn before they part
    lines = deck(c, [A, B], [("el", "solid"), ("el", "solid")], [(v, 0, 0), (-v, 0, 0)], 1.6 * T,
                 (c["type"], c["lag"]))
    exact = not c.get("rot")
    pairs = []
    if c["align"] == "node" and c["ratio"] == "1:1" and exact:
        # facing end nodes, node on node: their x gap in nodout, fine in time
        off = len(A.x) + 1000 - (len(A.x) % 1000)
        ia = [i for i in range(len(A.x)) if abs(A.x[i, 0] - L) < 1e-12]
        ib = {(round(B.x[i, 1], 12), round(B.x[i, 2], 12)): i for i in range(len(B.x))
              if abs(B.x[i, 0] - L - gap) < 1e-12}
        pairs = [(i + 1, off + ib[(round(A.x[i, 1], 12), round(A.x[i, 2], 12))] + 1) for i in ia]
        ids = [p for q in pairs for p in q]
        lines += ["*DATABASE_NODOUT", g.f10(1.6 * T / 2000), "*DATABASE_HISTORY_NODE"]
        lines += ["".join(f"{n:10d}" for n in ids[j:j + 8]) for j in range(0, len(ids), 8)]
    ans = {"kind": "rebound" if exact else "bounce", "axis": 0, "v_end": [-v, v], "v0": [v, -v],
           "tol": c.get("tol", 0.05), "duration": 2 * L / C if exact else None, "overlap": 0.5,
           "pairs": pairs, "h": h, "glance": bool(c.get("rot")) and c["rot"][1] >= 45}
    return lines, ans


def plates(c):
    """Two equal elastic square plates face to face at +-v (through-
    thickness rigid): an elastic two-mass collision, the velocities swap."""
    W, k, t = 0.02, c["k"], c["t"]
    gap = t + 2.0e-5
    A = shell_grid(lin(0, W, k), lin(0, W, k), lambda u, v: (u, v, 0.0))
    kb = {"1:1": k, "1:3": 3 * k, "3:1": max(1, k // 3)}[c["ratio"]]
    rng = random.Random(c["seed"])
    us = {"node": lin(0, W, kb), "half": shifted(0, W, kb), "rand": jittered(0, W, kb, rng)}[c["align"]]
    B = shell_grid(us, us, lambda u, v: (u, v, gap))
    if c.get("rot"):
        B = B.moved(rot(c["rot"][0], c["rot"][1]), about=(W / 2, W / 2, gap))
        B = B.moved(shift=(0, 0, gap - B.x[:, 2].min()))   # its lowest point the gap above
    v = c["v"]
    T = 2.0e-5 / (2 * v) + 2.0 * spring_time(RHO * t * W * W, W / max(k, kb), W * W)
    if c.get("rot"):
        T += W / v  # edge first: the plate turns flat before the two part
    lines = deck(c, [A, B], [("el", t), ("el", t)], [(0, 0, v), (0, 0, -v)], 2 * T, (c["type"], c["lag"]))
    tilt = c.get("rot") and not (c["rot"][0] == "z" and c["rot"][1] <= 15)
    # Lagrangian projection: the constraint stops the approach and shells
    # have no through-thickness compliance to give it back, so the plates
    # end with their common velocity (a perfectly inelastic impact, which
    # momentum fixes); penalty: the spring gives it back, they swap
    v_end = [0.0, 0.0] if c["lag"] else [-v, v]
    ans = {"kind": "bounce" if tilt else "rebound", "axis": 2, "v_end": v_end, "v0": [v, -v],
           "tol": c.get("tol", 0.05), "overlap": 0.5}
    return lines, ans


def shell_on_block(c):
    """An elastic plate flat onto a free rigid block of the same mass:
    equal masses, elastic: the plate stops, the block takes its speed."""
    W, k, t = 0.02, c["k"], c["t"]
    kb = {"1:1": k, "1:3": 3 * k, "3:1": max(1, k // 3)}[c["ratio"]]
    rng = random.Random(c["seed"])
    us = {"node": lin(0, W, kb), "half": shifted(0, W, kb), "rand": jittered(0, W, kb, rng)}[c["align"]]
    hb = t  # a block as heavy as the plate
    gap = c.get("gap", 2.0e-5)   # the plate's contact surface this far above the block
    A = shell_grid(us, us, lambda u, v: (u, v, hb + 0.5 * t + gap))
    B = hex_block(lin(0, W, k), lin(0, W, k), lin(0, hb, 1))
    if c.get("rot"):
        z0 = A.x[:, 2].min()
        A = A.moved(rot(c["rot"][0], c["rot"][1]))
        A = A.moved(shift=(0, 0, z0 - A.x[:, 2].min()))   # its lowest point as high as before
    v = c["v"]
    T = gap / v + 2.0 * spring_time(RHO * t * W * W, W / max(k, kb), W * W)
    if c.get("rot"):
        T += W / v  # edge first: the plate turns flat before it leaves
    lines = deck(c, [A, B], [("el", t), ("rigid_free", "solid")], [(0, 0, -v), (0, 0, 0)], 2 * T,
                 (c["type"], c["lag"]))
    tilt = c.get("rot") and not (c["rot"][0] == "z" and c["rot"][1] <= 15)
    # penalty: equal masses on a spring swap velocities; Lagrange: the
    # common velocity v/2 (see plates)
    v_end = [-v / 2, -v / 2] if c["lag"] else [0.0, -v]
    ans = {"kind": "bounce" if tilt else "rebound", "axis": 2, "v_end": v_end, "v0": [-v, 0.0],
           "tol": c.get("tol", 0.05), "overlap": 0.5, "scale": v}
    return lines, ans


def edge_on_face(c):
    """A plate (nu = 0 membrane bar, length L) edge-first onto a fixed
    rigid block: a bar on a wall, full reversal after 2L/c."""
    L, W, k, t = 0.02, 0.01, c["k"], c["t"]
    n = 20  # along: the membrane bar's own 1-D error is that of 20 elements (2.5-5.3%, see bars)
    z0 = 0.5 * t + 2.0e-5  # the edge's contact surface (half a thickness out) 20 um off the face
    A = shell_grid(lin(0, W, k), lin(0, L, n), lambda u, v: (u, 0.005, z0 + v))
    B = hex_block(lin(-0.005, W + 0.005, k + 1), lin(0, 0.01, 2), lin(-0.004, 0, 1))
    if c.get("rot"):
        A = A.moved(rot(c["rot"][0], c["rot"][1]), about=(W / 2, 0.005, 2.0e-5))
        A = A.moved(shift=(0, 0, z0 - A.x[:, 2].min()))
    v = c["v"]
    T = 2.0e-5 / v + 2 * L / C + 2.0 * spring_time(RHO * t * W * L, W / k, W * W / k / 2)
    lines = deck(c, [A, B], [("el", t), ("rigid_fixed", "solid")], [(0, 0, -v), (0, 0, 0)], 1.6 * T,
                 (c["type"], c["lag"]))
    ans = {"kind": "bounce" if c.get("rot") else "rebound", "axis": 2, "v_end": [v, 0.0], "v0": [-v, 0.0],
           "tol": c.get("tol", 0.06), "overlap": 0.5, "parts": [0]}
    return lines, ans


def coplanar(c):
    """Two plates in one plane (z fixed) pushed edge to edge: equal nu = 0
    membrane bars head-on, full reversal (the in-plane tube of 5.2)."""
    L, W, k, t = 0.02, 0.01, c["k"], c["t"]
    n = 20  # along, as edge_on_face
    gap = t + 2.0e-5
    A = shell_grid(lin(0, L, n), lin(0, W, k), lambda u, v: (u, v, 0.0))
    kb = {"1:1": k, "1:3": 3 * k, "3:1": max(1, k // 3)}[c["ratio"]]
    rng = random.Random(c["seed"])
    vs = {"node": lin(0, W, kb), "half": shifted(0, W, kb), "rand": jittered(0, W, kb, rng)}[c["align"]]
    B = shell_grid(lin(L + gap, 2 * L + gap, n), vs, lambda u, v: (u, v, 0.0))
    v = c["v"]
    T = 2.0e-5 / (2 * v) + 2 * L / C + 2.0 * spring_time(RHO * t * W * L, W / k, W * W / k / 2)
    lines = deck(c, [A, B], [("el", t), ("el", t)], [(v, 0, 0), (-v, 0, 0)], 1.6 * T, (c["type"], c["lag"]),
                 spc=[(1, (0, 0, 1, 0, 0, 0)), (2, (0, 0, 1, 0, 0, 0))])
    ans = {"kind": "rebound", "axis": 0, "v_end": [-v, v], "v0": [v, -v], "tol": c.get("tol", 0.06),
           "overlap": 0.5, "gap_axis": 0}
    return lines, ans


def crossed_edges(c):
    """Two plates in perpendicular planes, leading edges crossing at right
    angles, head-on at +-v: the edges must not pass (edge across edge).
    align "node": the edges cross at a node of each; "half": half an
    element from any node (no node comes near the other plate: only an
    edge-to-edge contact, *CONTACT_AUTOMATIC_GENERAL, holds them)."""
    L, W, k, t = 0.02, 0.01, c["k"], c["t"]
    n = 2 * k
    m = 2 * (k // 2) or 2
    h = W / m if c["align"] == "half" else 0.0
    gap = t + 2.0e-5
    A = shell_grid(lin(0, L, n), lin(-W / 2 + h / 2, W / 2 + h / 2, m), lambda u, v: (u, 0.0, v))
    B = shell_grid(lin(L + gap, 2 * L + gap, n), lin(-W / 2 + h / 2, W / 2 + h / 2, m), lambda u, v: (u, v, 0.0))
    v = c["v"]
    T = 2.0e-5 / (2 * v) + 2 * L / C + 2.0 * spring_time(RHO * t * W * L, W / k, W * t)
    lines = deck(c, [A, B], [("el", t), ("el", t)], [(v, 0, 0), (-v, 0, 0)], 1.6 * T, (c["type"], c["lag"]))
    ans = {"kind": "bounce", "axis": 0, "v0": [v, -v], "overlap": 0.5, "edges": (L, gap, t), "tol": 0.0}
    return lines, ans


def corner_on_face(c):
    """An elastic cube corner-first (rotated about two axes) onto a fixed
    rigid block: no penetration, it bounces."""
    a, k = 0.01, c["k"]
    A = hex_block(lin(0, a, k), lin(0, a, k), lin(0, a, k))
    R = rot("x", c["rot"][1]) @ rot("y", 35.26)
    A = A.moved(R)
    A = A.moved(shift=(0.01 - A.x[:, 0].mean(), 0.01 - A.x[:, 1].mean(), 2.0e-5 - A.x[:, 2].min()))
    B = hex_block(lin(0, 0.02, 2 * k), lin(0, 0.02, 2 * k), lin(-0.004, 0, 1))
    v = c["v"]
    # a corner-first cube tips over onto an edge or face before it leaves:
    # that takes about its size over its speed
    T = 2.0e-5 / v + 10 * a / C + 3 * a / v
    lines = deck(c, [A, B], [("el", "solid"), ("rigid_fixed", "solid")], [(0, 0, -v), (0, 0, 0)], T,
                 (c["type"], c["lag"]))
    ans = {"kind": "bounce", "axis": 2, "v0": [-v, 0.0], "overlap": 0.5, "tol": 0.0, "parts": [0],
           "glance": c["lag"]}
    return lines, ans


def folding_strip(c):
    """A C-shaped strip (two arms joined by a web) whose arms close on
    each other at +-v: self-contact of one body; the arms must not pass."""
    L, W, D, k, t = 0.02, 0.01, 0.004, c["k"], c["t"]
    n = 2 * k
    xs, ys = lin(0, L, n), lin(0, W, k)
    nz = 2
    pts, idx = [], {}

    def node(p):
        key = tuple(round(q, 12) for q in p)
        if key not in idx:
            idx[key] = len(pts)
            pts.append(p)
        return idx[key]
    quads = []
    for zarm in (0.0, D):
        for j in range(k):
            for i in range(n):
                quads.append((node((xs[i], ys[j], zarm)), node((xs[i + 1], ys[j], zarm)),
                              node((xs[i + 1], ys[j + 1], zarm)), node((xs[i], ys[j + 1], zarm))))
    zs = lin(0, D, nz)
    for j in range(k):
        for m in range(nz):
            quads.append((node((L, ys[j], zs[m])), node((L, ys[j], zs[m + 1])),
                          node((L, ys[j + 1], zs[m + 1])), node((L, ys[j + 1], zs[m]))))
    A = Body(pts, quads, "shell")
    v = c["v"]
    lines = deck(c, [A], [("el", t)], [(0, 0, 0)], 1.0, ("single", c["lag"]))
    # arms at +-v (the web's nodes in proportion), set node by node
    z = A.x[:, 2]
    vel = v * (1 - 2 * z / D)
    end = (D - t - 2.0e-5) / (2 * v) + 2 * L / C
    out = list(lines)
    i = out.index("*NODE")
    card = ["*INITIAL_VELOCITY_NODE"] + [g.f10(n + 1, 0.0, 0.0, float(vv)) for n, vv in enumerate(vel)]
    out[i:i] = card
    out[out.index("*CONTROL_TERMINATION") + 1] = g.f10(2.5 * end, 0)
    j = out.index("*DATABASE_BINARY_D3PLOT")
    out[j + 1] = g.f10(2.5 * end / 25)
    for key in ("*DATABASE_GLSTAT", "*DATABASE_MATSUM"):
        j = out.index(key)
        out[j + 1] = g.f10(2.5 * end / 100)
    ans = {"kind": "bounce_self", "axis": 2, "overlap": 0.5, "tol": 0.0, "arms": D}
    return out, ans


FAMILIES = {"bars": bars, "plates": plates, "shell_on_block": shell_on_block, "edge_on_face": edge_on_face,
            "coplanar": coplanar, "crossed_edges": crossed_edges, "corner_on_face": corner_on_face,
            "folding_strip": folding_strip}

PAIR = {"bars": "solid-solid", "plates": "shell-shell", "shell_on_block": "shell on solid face",
        "edge_on_face": "shell edge on face", "coplanar": "shell edge on shell edge (coplanar)",
        "crossed_edges": "shell edge across shell edge", "corner_on_face": "solid corner on face",
        "folding_strip": "self-contact, folding strip"}


# ------------------------------------------------------------------ cases

def cases():
    """The product, thinned where a full product would repeat itself: each
    family varies alignment, mesh ratio, elements across, speed,
    thickness, enforcement and contact type."""
    out = []

    def add(fam, **kw):
        kw.setdefault("seed", len(out))
        kw.setdefault("lag", False)
        kw.setdefault("type", "single")
        kw.setdefault("ratio", "1:1")
        kw.setdefault("align", "node")
        tag = [fam, kw["type"], "lag" if kw["lag"] else "pen", kw["align"], kw["ratio"].replace(":", "to"),
               f"k{kw['k']}", f"v{kw['v']:g}"]
        if "t" in kw:
            tag.append(f"t{kw['t'] * 1e3:g}mm")
        if kw.get("rot"):
            tag.append(f"rot{kw['rot'][0]}{kw['rot'][1]}")
        if "n" in kw:
            tag.append(f"n{kw['n']}")
        kw["name"] = "_".join(tag)
        kw["family"] = fam
        out.append(kw)

    def face_to_face(fam):
        """A sheet meeting a face flat: thickness x alignment x enforcement
        x contact type (nodes to surface aligned only: one-way, see the
        bars)."""
        for t in (0.1e-3, 1.0e-3, 5.0e-3):
            for align in ("node", "half", "rand"):
                for lag in (False, True):
                    for typ in ("single", "s2s", "nts"):
                        if typ == "nts" and align != "node":
                            continue
                        add(fam, k=4, v=10.0, t=t, align=align, lag=lag, type=typ)

    # solid-solid bars: the aligned acceptance family (n = 80 along), then
    # the product at n = 20
    for k in (2, 3, 4):
        for lag in (False, True):
            add("bars", k=k, n=160, v=10.0, lag=lag, tol=0.02, accept=True)
    # (n = 40 along: the lumped-mass bar's own rebound error is 2.0%
    # (penalty) and 3.4% (Lagrange) there, measured one element across;
    # the tolerance 5% leaves the contact 1.6 to 3 points.) Nodes to
    # surface is one-way: its slave side must be the finer mesh, or the
    # master's nodes go through the slave's faces by design (LS-DYNA's
    # advice too); it runs aligned and with the slave three times finer.
    for k in (1, 2, 3, 4):
        for align in ("node", "half", "rand"):
            for lag in (False, True):
                for typ in ("single", "s2s", "nts"):
                    if typ == "nts" and align != "node":
                        continue
                    add("bars", k=k, n=40, v=10.0, align=align, lag=lag, type=typ)
    for v in (1.0, 100.0, 1000.0):
        for lag in (False, True):
            for k in (2, 4):
                add("bars", k=k, n=40, v=v, lag=lag, tol=0.05 if v < 1000 else 0.10)
    for ratio in ("1:3", "3:1"):
        for k in (3,):
            for lag in (False, True):
                for typ in ("single", "s2s", "nts"):
                    if typ == "nts" and ratio == "1:3":
                        continue
                    add("bars", k=k, n=40, v=10.0, ratio=ratio, lag=lag, type=typ)
    for ax in ("x", "y", "z"):
        for deg in (15, 30, 45):
            for lag in (False, True):
                add("bars", k=3, n=40, v=10.0, rot=(ax, deg), lag=lag)
    # shell-shell plates
    face_to_face("plates")
    for v in (1.0, 100.0, 1000.0):
        for t in (0.5e-3, 2.0e-3):
            for lag in (False, True):
                add("plates", k=4, v=v, t=t, lag=lag)
    for ratio in ("1:3", "3:1"):
        for lag in (False, True):
            add("plates", k=3, v=10.0, t=1.0e-3, ratio=ratio, lag=lag)
    for ax in ("x", "y", "z"):
        for deg in (15, 45):
            add("plates", k=4, v=10.0, t=1.0e-3, rot=(ax, deg))
    # shell on a solid face
    face_to_face("shell_on_block")
    for v in (1.0, 100.0, 1000.0):
        for lag in (False, True):
            add("shell_on_block", k=4, v=v, t=1.0e-3, lag=lag)
    for ratio in ("1:3", "3:1"):
        add("shell_on_block", k=3, v=10.0, t=1.0e-3, ratio=ratio)
    for ax in ("x", "z"):
        for deg in (15, 45):
            add("shell_on_block", k=4, v=10.0, t=1.0e-3, rot=(ax, deg))
    # shell edge on a face
    # (edge-on families: thickness up to the element length along, 1 mm;
    # a sheet ten times thicker than its elements are long is no model)
    for t in (0.1e-3, 0.5e-3, 1.0e-3):
        for k in (1, 2, 4):
            for lag in (False, True):
                for typ in ("single", "nts"):
                    add("edge_on_face", k=k, v=10.0, t=t, lag=lag, type=typ)
    for v in (1.0, 100.0):
        add("edge_on_face", k=2, v=v, t=1.0e-3)
    for deg in (15, 30, 45):
        add("edge_on_face", k=2, v=10.0, t=1.0e-3, rot=("y", deg))
    # coplanar edges
    for t in (0.1e-3, 0.5e-3, 1.0e-3):
        for align in ("node", "half", "rand"):
            for lag in (False, True):
                add("coplanar", k=2, v=10.0, t=t, align=align, lag=lag)
    for typ in ("s2s", "nts"):
        add("coplanar", k=2, v=10.0, t=1.0e-3, type=typ)
    # crossed edges
    for t in (0.5e-3, 1.0e-3, 5.0e-3):
        for k in (2, 4):
            for lag in (False, True):
                add("crossed_edges", k=k, v=10.0, t=t, lag=lag)
    # crossed edges half an element from any node: edge to edge (general)
    for t in (0.5e-3, 1.0e-3, 5.0e-3):
        for k in (2, 4):
            add("crossed_edges", k=k, v=10.0, t=t, type="general", align="half")
    add("crossed_edges", k=2, v=100.0, t=1.0e-3, type="general", align="half")
    add("crossed_edges", k=2, v=10.0, t=1.0e-3, type="general")
    add("crossed_edges", k=2, v=100.0, t=1.0e-3)
    add("crossed_edges", k=2, v=100.0, t=1.0e-3, type="general")
    add("crossed_edges", k=2, v=10.0, t=1.0e-3, type="general", align="half", lag=True)
    add("crossed_edges", k=2, v=10.0, t=1.0e-3, align="half")
    # solid corner on a face
    for deg in (0, 15, 30, 45):
        for k in (1, 2, 3):
            for lag in (False, True):
                add("corner_on_face", k=k, v=10.0, rot=("x", deg), lag=lag)
    for v in (1.0, 100.0):
        add("corner_on_face", k=2, v=v, rot=("x", 15))
    # self-contact of a folding strip
    for t in (0.1e-3, 0.5e-3, 1.0e-3):
        for k in (1, 2, 4):
            for lag in (False, True):
                add("folding_strip", k=k, v=10.0, t=t, lag=lag)
    return out


# Known exceptions: cases that fail their answer today, each with its
# reason (the figures are in doc/contact-suite.md). A failing case that
# matches none of these fails the suite.
EXCEPTIONS = [
    (r"_pen_.*_v1000", "penalty at 1000 m/s: the spring cannot carry rho c v (40 GPa steel on steel) within the "
                       "depth window (SLSFAC 1 for solids, 0.1 for shells): the bodies overlap or pass; use a "
                       "higher SLSFAC or ENFORCE 2"),
    (r"^crossed_edges_single_pen_half_", "a single surface has no edge-to-edge contact (nor has LS-DYNA's "
                                        "AUTOMATIC_SINGLE_SURFACE): edges crossing half an element from any node "
                                        "pass; AUTOMATIC_GENERAL holds them (the general_half cases). Kept to show "
                                        "that the check sees the pass"),
    (r"^crossed_edges_single_pen_node_1to1_k2_v100_", "the node contact's edge tube has no side: at 200 m/s closing "
                                                      "the node at the crossing is driven past the other edge's axis "
                                                      "and pushed on through (open); AUTOMATIC_GENERAL's edge pairs "
                                                      "keep the side and turn the edges back"),
    (r"^crossed_edges_general_pen_.*_v100_", "200 m/s closing on one point of two 1 mm edges: the spring of one "
                                             "node (SLSFAC 0.1) cannot carry the plates' rho c v within the "
                                             "thickness; the edges overlap by 1.6-2.9 thicknesses, are turned back "
                                             "on their own sides and part"),
    (r"^bars_single_lag_node_1to1_k2_v1000", "1000 m/s is 20% strain (v / c = 0.2): the bar leaves the linear 1-D "
                                              "answer (large strain, the hexahedra's geometry); since the projection "
                                              "runs at the elements' step (no contact step bound: it has no springs, "
                                              "issue 28) a node moves 18% of an element a step, the ends overlap by "
                                              "1.04 of the window and one missed contact is found 1.29e-3 deep "
                                              "against the search's bound of 9.26e-4 (open)"),
    (r"^(plates|shell_on_block)_.*_(1to3|3to1)_", "non-matching meshes: node-to-segment forces are not uniform "
                                                   "(the patch test's corner excess), so the plates bend and keep "
                                                   "vibration energy"),
    (r"^bars_single_lag_rand_1to1_k2_v10_n40$", "5.9% against 5%: the Lagrangian bar's own error at 40 elements is "
                                                 "3.4%, the random mesh adds 2.5 points"),
]


def exception_for(name):
    for pat, why in EXCEPTIONS:
        if re.search(pat, name):
            return why
    return None


FAST = ("bars_single_pen_node_1to1_k2_v10_n160", "bars_single_lag_node_1to1_k2_v10_n160",
        "bars_single_pen_node_1to1_k3_v10_n160", "bars_single_lag_node_1to1_k3_v10_n160",
        "bars_single_pen_node_1to1_k4_v10_n160", "bars_single_lag_node_1to1_k4_v10_n160")


def fast_subset(all_cases):
    """About 40 cases: the six aligned acceptance bars and up to five of
    each family, spread evenly over its list (deterministic), known
    exceptions left out."""
    picked = [c for c in all_cases if c["name"] in FAST]
    fams = {}
    for c in all_cases:
        if c["name"] not in FAST and not exception_for(c["name"]):
            fams.setdefault(c["family"], []).append(c)
    for fam, lst in fams.items():
        step = max(1, len(lst) // 5)
        picked += lst[::step][:5]
    return picked


# ------------------------------------------------------------------- runs

def read_d3hsp(path):
    txt = open(path).read() if os.path.exists(path) else ""
    worst = 0.0
    m = re.search(r"max 4u/delta\n((?:\s+\d+.*\n)+)", txt)
    if m:
        for ln in m.group(1).splitlines():
            f = ln.split()
            if f and f[0].isdigit():
                worst = max(worst, float(f[-1]))
    late = sum(int(x) for x in re.findall(r": (\d+) (?:missed )?contacts found \(or moved\) deeper", txt))
    rel = sum(int(x) for x in re.findall(r": (\d+) contacts released", txt))
    back = sum(int(x) for x in re.findall(r": (\d+) contacts back under the segment", txt))
    within = sum(int(x) for x in re.findall(r": (\d+) contacts deep in a shell's zone", txt))
    hand = sum(int(x) for x in re.findall(r": (\d+) contacts moved to a segment deeper", txt))
    return worst, late, rel, back, within, hand


def read_events(path):
    """The allowance events d3hsp names: the pool margin delta, the largest
    segment thickness (a solid face's: its depth window), the excess of
    every missed contact named, and the initial penetrations left at the
    first cycle."""
    txt = open(path).read() if os.path.exists(path) else ""
    # (the typical margin, the largest a node has: the margins follow the
    # local size below it, and each node's motion since the last search is
    # held to a quarter of the least margin around it)
    m = re.search(r"pool margins delta min/median/max +\S+ +(\S+)", txt)
    delta = float(m.group(1)) if m else float("nan")
    m = re.search(r"segment thickness min/max +\S+ +(\S+)", txt)
    tmax = float(m.group(1)) if m else 0.0
    missed = [float(x) for x in re.findall(r"missed contact \(entered since the search\).*depth +(\S+)", txt)]
    initial = len(re.findall(r"initial penetration \(allowed\)", txt))
    return delta, tmax, missed, initial


def evaluate(c, ans, d, rc, wall):
    res = {"name": c["name"], "family": c["family"], "wall": wall, "rc": rc, "fails": [], "err": float("nan"),
           "answer": ""}
    if rc != 0:
        res["fails"].append(f"exit {rc}")
        return res
    with h5py.File(os.path.join(d, "thist.h5"), "r") as f:
        ratio = f["glstat/energy_ratio"][:]
        slide = f["glstat/sliding_interface_energy"][:]
        ke0 = f["glstat/kinetic_energy"][0]
        ms = f["matsum"]
        mass = ms["mass"][-1]
        ax = "xyz"[ans["axis"]]
        mom = ms[f"{ax}_momentum"][:]
        tm = ms["time"][:]
    vend = mom[-1] / np.maximum(mass, 1e-300)
    if c["family"] not in ("edge_on_face", "corner_on_face"):
        # no fixed body: the contact forces are equal and opposite, so the
        # total momentum along the axis stays what it was (round-off)
        tot = mom.sum(1)
        scale = math.sqrt(2.0 * mass.sum() * ke0)   # the momentum the initial motion amounts to
        res["momentum"] = float(np.abs(tot - tot[0]).max() / scale)
        if res["momentum"] > 1e-9:
            res["fails"].append(f"momentum changed by {res['momentum']:.1e} of the initial (band 1e-9)")
    worst, late, rel, back, within, hand = read_d3hsp(os.path.join(d, "d3hsp"))
    res["search"] = worst
    res["late"], res["rel"], res["back"], res["within"], res["hand"] = late, rel, back, within, hand
    res["ratio"] = float(np.max(np.abs(ratio - 1.0)))
    if res["ratio"] > 0.05:
        res["fails"].append(f"energy ratio off by {res['ratio']:.3f} (band 0.05)")
    # the energy ratio counts the contact's work as sliding energy, so it
    # cannot see a contact that creates energy: the sliding energy is the
    # work the bodies did on the springs, never negative for a frictionless
    # penalty contact (what its springs hold, less what they gave back).
    # Band: -0.1% of the initial kinetic energy at every output (issue 28);
    # the central difference's own error of a bounce whose spring is swept
    # over the step is below 1e-4 of its energy at the contact's step
    # bound, so 1e-3 leaves room for ten such bounces of the whole energy
    # (with the spring taken at x(n) alone, single impacts created up to
    # 2.8%; ke0 is never 0 here: every case starts from motion)
    ref = max(ke0, 1e-300)
    res["created"] = float(max(0.0, -slide.min()) / ref)
    if res["created"] > 1e-3:
        res["fails"].append(f"the contact created {res['created']:.4f} of the initial kinetic energy at its worst "
                            f"output (band 0.001)")
    if worst > 1.0 + 1e-9:
        res["fails"].append(f"max 4u/delta {worst:.3f} > 1")
    # every allowance event held to physics. A missed contact is a node that
    # lay outside the segment's zone at the last global search (within 1%
    # of the thickness or window) and is found in it now: every point of the
    # segment and the node each moved, relative to the surface's mean
    # motion, at most u since, and the search runs again before 4u exceeds
    # the least margin around a node (at most delta, the typical one), so its
    # depth, and the excess allowed, cannot exceed 2u + 1% of the thickness
    # <= delta / 2 + 1%. A larger
    # excess is a node that never crossed that face (a false contact). The
    # decks take IGNORE 0 (nodes moved out before the run), so no initial
    # penetration may be left at the first cycle.
    delta, tmax, missed, initial = read_events(os.path.join(d, "d3hsp"))
    bound = 0.5 * delta + 0.01 * tmax
    res["missed_checked"] = len(missed)
    res["missed_worst"] = max(missed) / bound if missed else 0.0
    bad = [e for e in missed if not e <= bound]
    if bad:
        res["fails"].append(f"{len(bad)} of {len(missed)} missed contacts deeper than a node's travel since the "
                            f"search allows (worst excess {max(bad):.2e} > delta/2 + 1% of the thickness = "
                            f"{bound:.2e}): false contacts")
    if initial:
        res["fails"].append(f"{initial} initial penetrations left at the first cycle (IGNORE 0 moves them out)")
    try:
        over, cross, _, _ = penetration.check_run(d)
    except Exception as e:  # noqa: BLE001
        over, cross = float("nan"), -1
        res["fails"].append(f"penetration checker: {e}")
    res["overlap"], res["cross"] = over, cross
    if cross > 0:
        res["fails"].append(f"{cross} pass-throughs")
    if not over <= ans["overlap"]:
        res["fails"].append(f"overlap {over:.3f} of the thickness > {ans['overlap']}")
    kind = ans["kind"]
    parts = ans.get("parts", range(len(ans.get("v0", []))))
    if kind == "rebound":
        scale = ans.get("scale", max(abs(x) for x in ans["v0"]))
        err = max(abs(vend[i] - ans["v_end"][i]) / scale for i in parts)
        res["err"] = float(err)
        res["answer"] = "rebound " + ", ".join(f"{ans['v_end'][i]:+g}" for i in parts) + " m/s"
        if err > ans["tol"]:
            res["fails"].append(f"rebound error {err:.3f} > {ans['tol']}")
        if ans.get("duration"):
            dp = np.gradient(mom[:, 0], tm)
            on = np.abs(dp) > 0.02 * np.abs(dp).max()
            dur = tm[on][-1] - tm[on][0] if on.any() else 0.0
            res["dur"] = float(dur / ans["duration"] - 1)
            if c.get("accept") and abs(res["dur"]) > 0.10:
                res["fails"].append(f"contact duration off 2L/c by {res['dur']:.3f} (tol 0.10)")
        if ans.get("pairs"):
            with h5py.File(os.path.join(d, "thist.h5"), "r") as f:
                ids = list(f["nodout/ids"][:])
                xx = f["nodout/x_coordinate"][:]
            gaps = np.array([xx[:, ids.index(b)] - xx[:, ids.index(a)] for a, b in ans["pairs"]])
            res["end_overlap"] = float(max(0.0, -gaps.min()) / ans["h"])
            if c.get("accept") and c["lag"] and res["end_overlap"] > 1e-9:
                res["fails"].append(f"facing ends overlap {res['end_overlap']:.2e} of the element length > 1e-9")
    elif kind == "bounce":
        # the bodies part: their relative velocity along the axis turned
        # round (an eccentric impact turns a body, so its centre need not
        # reverse; but free bodies that have touched never go on closing).
        # Error: end over initial relative velocity, must be <= 0.
        res["answer"] = "the bodies part (relative velocity reverses)"
        v0 = ans["v0"]
        rel0 = v0[0] - (v0[1] if len(v0) > 1 else 0.0)
        rel = vend[0] - (vend[1] if len(v0) > 1 and ans.get("parts", [0, 1]) != [0] else 0.0)
        ratio = rel / rel0
        res["err"] = float(ratio)
        if ans.get("glance"):
            # a glancing impact (bars meeting at 45 degrees slide off each
            # other; a cube on its corner topples with the Lagrangian
            # constraint): the contact must have acted, not let them through
            res["answer"] = "the impact acts (relative velocity along the axis falls by 10% or more)"
            if ratio > 0.9:
                res["fails"].append(f"no impact: end/initial relative velocity {ratio:.3f} > 0.9")
        elif ratio > 0.0:
            res["fails"].append(f"still closing: end/initial relative velocity {ratio:.3f} > 0")
    elif kind == "bounce_self":
        res["answer"] = "arms part again, no pass-through"
        res["err"] = 0.0
    return res


def run_case(c):
    d = os.path.join(OUT, c["name"])
    os.makedirs(d, exist_ok=True)
    lines, ans = FAMILIES[c["family"]](c)
    g.write(os.path.join(d, "deck.k"), lines)
    t0 = time.time()
    try:
        p = subprocess.run([XDYNA, "i=deck.k"], cwd=d, capture_output=True, text=True, timeout=LIMIT,
                           env={**os.environ, "OMP_NUM_THREADS": "1"})
        rc = p.returncode
    except subprocess.TimeoutExpired:
        rc = -1
    wall = time.time() - t0
    res = evaluate(c, ans, d, rc, wall)
    if c["family"] == "folding_strip" and rc == 0:
        res.update(strip_check(d, ans))
    if c["family"] == "crossed_edges" and rc == 0:
        res.update(edges_check(d, ans))
        # where the edges cross away from the nodes the node checker sees no
        # overlap: the edges' own is the case's
        if res.get("edge_overlap", 0.0) > res.get("overlap", 0.0):
            res["overlap"] = res["edge_overlap"]
    return res


def states(d):
    with h5py.File(os.path.join(d, "d3plot.h5"), "r") as f:
        names = sorted(k for k in f["states"] if k != "time")
        X = np.array([f[f"states/{k}/coordinates"][:] for k in names])
    return X


def strip_check(d, ans):
    """The arms' nodes: the top arm stays above the bottom arm."""
    X = states(d)
    z0 = X[0][:, 2]
    top = np.abs(z0 - ans["arms"]) < 1e-6
    bot = np.abs(z0) < 1e-6
    gap = X[:, top, 2].min(1) - X[:, bot, 2].max(1)
    out = {"err": float(gap.min())}
    if gap.min() <= 0.0:
        out["fails_extra"] = f"the arms crossed (smallest gap {gap.min():.2e} m)"
    return out


def edges_check(d, ans):
    """The leading edges: plate 2's stays ahead of plate 1's, no closer
    than the contact thickness less the overlap band (the edges' own
    overlap: the node checker sees no node near the other plate where the
    edges cross away from the nodes), and ends ahead."""
    X = states(d)
    L, gap, t = ans["edges"]
    x0 = X[0][:, 0]
    e1 = np.abs(x0 - L) < 1e-6
    e2 = np.abs(x0 - L - gap) < 1e-6
    sep = X[:, e2, 0].min(1) - X[:, e1, 0].max(1)
    depth = float(max(0.0, (t - sep).max()) / t)
    out = {"err": float(sep.min()), "edge_overlap": depth}
    if sep[-1] <= 0.0:
        out["fails_extra"] = f"the edges passed each other (end separation {sep[-1]:.2e} m)"
    elif sep.min() <= 0.0 or depth > ans["overlap"]:
        out["fails_extra"] = (f"the edges overlapped by {depth:.2f} of the thickness before they parted "
                              f"(band {ans['overlap']})")
    return out


PENMAX = None


def main(argv):
    global PENMAX, OUT
    fast = "--fast" in argv
    if "--penmax" in argv:
        PENMAX = float(argv[argv.index("--penmax") + 1])
        argv = argv + ["--no-report"]
        OUT = OUT + "-penmax"
    jobs = 2
    if "--jobs" in argv:
        jobs = int(argv[argv.index("--jobs") + 1])
    allc = cases()
    sel = fast_subset(allc) if fast else allc
    if "--only" in argv:
        sub = argv[argv.index("--only") + 1]
        sel = [c for c in sel if sub in c["name"]]
    if "--list" in argv:
        for c in sel:
            print(c["name"])
        print(f"{len(sel)} cases")
        return 0
    t0 = time.time()
    saved = os.path.join(OUT, "results.json")
    if "--report-only" in argv:
        with open(saved) as f:
            results = json.load(f)
    else:
        with ThreadPoolExecutor(max_workers=jobs) as ex:
            results = list(ex.map(run_case, sel))
        if not fast and "--only" not in argv:
            with open(saved, "w") as f:
                json.dump(results, f)
        elif "--merge" in argv and os.path.exists(saved):
            # the selected cases run again, the others as the last full run
            # left them: the report written from both
            with open(saved) as f:
                old = json.load(f)
            new = {r["name"]: r for r in results}
            results = [new.pop(r["name"], r) for r in old] + list(new.values())
            with open(saved, "w") as f:
                json.dump(results, f)
            argv = [a for a in argv if a != "--only"] + ["--report-only"]
    for r in results:
        if "fails_extra" in r:
            r["fails"].append(r.pop("fails_extra"))
    for r in results:
        r["exception"] = exception_for(r["name"]) if r["fails"] else None
    nfail = sum(1 for r in results if r["fails"])
    nexc = sum(1 for r in results if r["exception"])
    for r in results:
        st = "ok  " if not r["fails"] else ("EXC " if r["exception"] else "FAIL")
        print(f"{st} {r['name']:70s} err {r['err']:+.4f} {r['wall']:6.2f}s {'; '.join(r['fails'])}")
    print(f"contact suite: {len(results) - nfail} of {len(results)} cases pass, {nexc} listed exceptions, "
          f"{nfail - nexc} unexplained failures ({time.time() - t0:.0f} s)")
    crush = None
    crush_saved = os.path.join(OUT, "crush.json")
    if "--report-only" in argv and os.path.exists(crush_saved):
        # (the crush family's rows of the last full run)
        with open(crush_saved) as f:
            crush = json.load(f)
    if not fast and "--only" not in argv and "--report-only" not in argv:
        # the crush family (tools/crush_family.py): tubes against
        # Abramowicz and Jones, with the contact and without
        crush = crush_family.run_family(jobs)
        with open(crush_saved, "w") as f:
            json.dump(crush, f, default=float)
        ncr = sum(1 for r in crush if r["ok"])
        print(f"crush family: {ncr} of {len(crush)} tubes within {crush_family.BAND:.0%} of Abramowicz and Jones "
              f"(table in {os.path.relpath(REPORT, ROOT)})")
    if not fast and "--no-report" not in argv and "--only" not in argv:
        write_report(results, crush)
    return 1 if nfail > nexc or (crush and not all(r["ok"] for r in crush)) else 0


def write_report(results, crush=None):
    fams = {}
    for r in results:
        fams.setdefault(r["family"], []).append(r)
    out = ["# Contact torture suite", "",
           "Written by `make contact-suite` (tools/contact_suite.py); do not edit. Each case is a generated",
           "deck held to exit 0, the energy ratio within 5%, max 4u/delta <= 1, no pass-through and a worst",
           "overlap under half the thickness (tools/penetration.py), and its answer: the closed-form rebound",
           "(error: |v_end - v_exact| / v0, the case's tolerance in its row) or the bodies parting (error:",
           "end over initial relative velocity, must be <= 0); crossed edges and the folding strip: the smallest",
           "separation of the two edges or arms over the states, in metres (must stay positive).", "",
           "Every missed contact d3hsp names (an allowance: found deeper than a step in a zone the node entered",
           "since the last search) is checked: its excess cannot exceed the node's travel since the search,",
           "at most delta / 2 + 1% of the thickness; the worst ratio of a passing case is in the table.",
           "A contact back under the segment its node held last (the local search lets it through without",
           "asking whether the node came in since the search: it was on that segment's contact side) is",
           "counted apart; its case's pass-through check holds it (such a node must not have crossed).",
           "So is a contact deep in a shell's zone the node already lay in at the search (it never crossed",
           "into it): held at the depth found, no force until it goes deeper; its case's pass-through and",
           "energy checks hold it. So is a contact moved to another segment deeper than the old segment's",
           "spring would be at the node's place (two segments measure depth differently where they meet):",
           "the excess is allowed, so the move neither adds nor takes spring energy.", "",
           "Energy: a frictionless contact never does net positive work, so every case's sliding energy",
           "(glstat) must stay above -0.1% of the initial kinetic energy at every output; the table gives",
           "the worst energy created over the passing cases (the lowest sliding energy, as a share of the",
           "initial kinetic energy; 0 where it never went below zero).", "",
           "| pair | cases | pass | exceptions | worst rebound error (passing cases) | worst overlap | energy created, "
           "worst (passing cases) | contacts deeper "
           "than a step (excess allowed) | checked | worst excess / bound (passing cases) | back under the segment held "
           "last (cases with pass-throughs) | held deep in a shell's zone (cases with pass-throughs) | moved to a "
           "segment deeper than the old one's spring (cases with pass-throughs) | contacts released deep |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for fam, lst in fams.items():
        errs = [abs(r["err"]) for r in lst if r["answer"].startswith("rebound") and not r["fails"]]
        ov = [r.get("overlap", 0) for r in lst if r.get("overlap", 0) == r.get("overlap", 0) and not r["fails"]]
        out.append(f"| {PAIR[fam]} | {len(lst)} | {sum(1 for r in lst if not r['fails'])} | "
                   f"{sum(1 for r in lst if r['exception'])} | "
                   f"{max(errs) if errs else float('nan'):.4f} | {max(ov) if ov else 0:.3f} | "
                   f"{max([r.get('created', 0) for r in lst if not r['fails']] or [0]):.1e} | "
                   f"{sum(r.get('late', 0) for r in lst)} | {sum(r.get('missed_checked', 0) for r in lst)} | "
                   f"{max([r.get('missed_worst', 0) for r in lst if not r['fails']] or [0]):.3f} | "
                   f"{sum(r.get('back', 0) for r in lst)} "
                   f"({sum(1 for r in lst if r.get('back', 0) and r.get('cross', 0) != 0)}) | "
                   f"{sum(r.get('within', 0) for r in lst)} "
                   f"({sum(1 for r in lst if r.get('within', 0) and r.get('cross', 0) != 0)}) | "
                   f"{sum(r.get('hand', 0) for r in lst)} "
                   f"({sum(1 for r in lst if r.get('hand', 0) and r.get('cross', 0) != 0)}) | "
                   f"{sum(r.get('rel', 0) for r in lst)} |")
    npass = sum(1 for r in results if not r["fails"])
    nexc = sum(1 for r in results if r["exception"])
    out += ["", f"{len(results)} cases: {npass} pass, {nexc} fail as listed exceptions, "
            f"{len(results) - npass - nexc} unexplained failures; {sum(r['wall'] for r in results):.0f} s of runs.",
            "", "## Exceptions", "", "| cases (pattern) | count | reason |", "|---|---|---|"]
    for pat, why in EXCEPTIONS:
        n = sum(1 for r in results if r["exception"] == why)
        out.append(f"| `{pat}` | {n} | {why} |")
    if crush is not None:
        out += [""] + crush_family.markdown(crush)
    out += ["", "## Cases", "", "| case | answer | error | overlap | energy created | 4u/delta | wall (s) | result |",
            "|---|---|---|---|---|---|---|---|"]
    for r in results:
        res = "pass" if not r["fails"] else ("exception: " if r["exception"] else "FAIL: ") + "; ".join(r["fails"])
        if "end_overlap" in r:
            res += f" (facing ends overlap {r['end_overlap']:.1e} of an element)"
        out.append(f"| {r['name']} | {r['answer']} | {r['err']:+.4f} | {r.get('overlap', float('nan')):.3f} | "
                   f"{r.get('created', float('nan')):.1e} | "
                   f"{r.get('search', float('nan')):.3f} | {r['wall']:.2f} | {res} |")
    with open(REPORT, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
