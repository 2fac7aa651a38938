#!/usr/bin/python3
"""Generate xdyna's verification, demo and benchmark decks.

    gen_decks.py [--outdir input_decks] [--bench NX NY NZ FILE]

The decks in input_decks/ are committed; rerun this script to regenerate
them (or to refine a mesh) after changing it. Units are SI (m, kg, s, Pa).
"""
import argparse
import math
import os


def block_mesh(nx, ny, nz, lx, ly, lz, origin=(0.0, 0.0, 0.0), nid0=1, eid0=1):
    """Nodes {id: (x,y,z)} and hexes [(eid, n1..n8)] of a structured block."""
    nodes = {}
    def nid(i, j, k):
        return nid0 + i + (nx + 1) * (j + (ny + 1) * k)
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                nodes[nid(i, j, k)] = (origin[0] + lx * i / nx, origin[1] + ly * j / ny,
                                       origin[2] + lz * k / nz)
    hexes = []
    e = eid0
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                hexes.append((e, nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                              nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1),
                              nid(i, j + 1, k + 1)))
                e += 1
    return nodes, hexes


def node_cards(nodes):
    out = ["*NODE", "$#   nid               x               y               z      tc      rc"]
    for n, (x, y, z) in sorted(nodes.items()):
        out.append(f"{n:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}")
    return out


def solid_cards(hexes, pid):
    out = ["*ELEMENT_SOLID", "$#   eid     pid      n1      n2      n3      n4      n5      n6      n7      n8"]
    for h in hexes:
        out.append(f"{h[0]:8d}{pid:8d}" + "".join(f"{n:8d}" for n in h[1:]))
    return out


def grid_shell_cards(nx, ny, pid=1):
    """*ELEMENT_SHELL cards of an nx x ny grid of quadrilaterals on nodes
    numbered 1 + i + (nx + 1) j, elements numbered from 1 row by row."""
    out = ["*ELEMENT_SHELL"]
    for j in range(ny):
        for i in range(nx):
            n1 = 1 + i + (nx + 1) * j
            out.append(f"{1 + i + nx * j:8d}{pid:8d}{n1:8d}{n1 + 1:8d}{n1 + nx + 2:8d}{n1 + nx + 1:8d}")
    return out


def f10(*vals):
    """Fields of ten columns: ints right-justified, reals in 10 characters."""
    s = ""
    for v in vals:
        if isinstance(v, int):
            s += f"{v:10d}"
        elif isinstance(v, str):
            s += f"{v:>10s}"
        else:
            t = f"{v:10.4g}"
            if len(t) > 10 or "e" in t:
                t = f"{v:10.3e}"
            s += t
    return s


def node_set(sid, ids):
    out = ["*SET_NODE_LIST", f10(sid)]
    ids = list(ids)
    for i in range(0, len(ids), 8):
        out.append("".join(f"{n:10d}" for n in ids[i:i + 8]))
    return out


def part(pid, mid, title, hgid=0):
    return ["*PART", title, f10(pid, 1, mid, 0, hgid)]


def common(title, endtim, dt_out, endcyc=0):
    return ["*KEYWORD", "*TITLE", title,
            "*CONTROL_TERMINATION", f10(endtim, endcyc),
            "*CONTROL_TIMESTEP", f10(0.0, 0.9),
            "*DATABASE_GLSTAT", f10(dt_out),
            "*DATABASE_MATSUM", f10(dt_out),
            "*SECTION_SOLID", f10(1, 1)]


def write(path, lines):
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n*END\n")


def nodes_where(nodes, pred):
    return [n for n, x in sorted(nodes.items()) if pred(*x)]


def bar_impact(outdir):
    """Elastic bar (nu = 0) moving at v0 stopped at x = 0 by SPCs: a stress
    wave of amplitude rho c v0 runs along it at c = sqrt(E/rho)."""
    L, a, n = 1.0, 0.005, 200
    E, rho, v0 = 200e9, 7850.0, 10.0
    nodes, hexes = block_mesh(n, 1, 1, L, a, a)
    fixed = nodes_where(nodes, lambda x, y, z: abs(x) < 1e-12)
    hist = [n_ for n_, x in sorted(nodes.items()) if x[1] == 0.0 and x[2] == 0.0 and
            any(abs(x[0] - d) < 1e-9 for d in (0.2, 0.25, 0.3, 0.5, 0.75))]
    lines = common("elastic bar struck at one end (1-D wave check)", 1.5e-4, 1.0e-6)
    lines += ["*DATABASE_NODOUT", f10(1.0e-6), "*DATABASE_HISTORY_NODE", "".join(f"{h:10d}" for h in hist)]
    lines += ["*MAT_ELASTIC", f10(1, rho, E, 0.0)]
    lines += part(1, 1, "bar")
    lines += node_set(1, fixed)
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 0, 0, 0)]
    lines += ["*INITIAL_VELOCITY", f10(0), f10(-v0, 0.0, 0.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "bar_impact.k"), lines)


def free_block_spin(outdir):
    """A free elastic block translating and spinning: energy must stay put."""
    nodes, hexes = block_mesh(4, 4, 4, 0.1, 0.1, 0.1)
    lines = common("free block translating and spinning (energy conservation)", 1.0, 1.0e-4, endcyc=10000)
    lines += ["*MAT_ELASTIC", f10(1, 2700.0, 70e9, 0.33)]
    lines += part(1, 1, "block")
    lines += ["*INITIAL_VELOCITY_GENERATION", f10(1, 2, 100.0, 3.0, -2.0, 1.0, 0, 0),
              f10(0.05, 0.05, 0.05, 0.3, 0.4, 1.0, 0, 0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "free_block_spin.k"), lines)


def prestressed_block(outdir):
    """A column with the axial stress of its first vibration mode, released
    on symmetry SPCs: the stored strain energy turns into vibration and the
    total energy is conserved. The stress is smooth (sigma0 cos(pi z / 2L),
    fixed base, free top) so that little energy sits in the mesh's highest
    modes, where central differences start with an O((omega dt)^2) error."""
    n, a, L = 4, 0.05, 0.2
    nodes, hexes = block_mesh(n, n, 2 * n, a, a, L)
    lines = common("pre-stressed column released under SPCs (energy balance)", 2.0e-4, 1.0e-6)
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3)]
    lines += part(1, 1, "column")
    lines += node_set(1, nodes_where(nodes, lambda x, y, z: z == 0.0))
    lines += node_set(2, nodes_where(nodes, lambda x, y, z: x == 0.0))
    lines += node_set(3, nodes_where(nodes, lambda x, y, z: y == 0.0))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 0, 0, 1), f10(2, 0, 1, 0, 0), f10(3, 0, 0, 1, 0)]
    lines += ["*INITIAL_STRESS_SOLID"]
    for h in hexes:
        zc = sum(nodes[k][2] for k in h[1:]) / 8
        # free format keeps every digit of the stress
        lines += [f"{h[0]},1", f"0.0,0.0,{1.0e8 * math.cos(math.pi * zc / (2 * L)):.12e},0.0,0.0,0.0"]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "prestressed_block.k"), lines)


def bar_wall(outdir):
    """Elastic bar (nu = 0) at v0 onto a planar rigid wall: contact lasts
    2L/c, the wall force is rho c A v0, the bar leaves at v0 (1-D theory)."""
    L, a, n = 1.0, 0.005, 200
    E, rho, v0 = 200e9, 7850.0, 10.0
    nodes, hexes = block_mesh(n, 1, 1, L, a, a, origin=(1.0e-6, 0.0, 0.0))
    lines = common("elastic bar on a planar rigid wall (1-D impact)", 6.0e-4, 2.0e-6)
    lines += ["*DATABASE_RWFORC", f10(1.0e-6)]
    lines += ["*MAT_ELASTIC", f10(1, rho, E, 0.0)]
    lines += part(1, 1, "bar")
    lines += ["*RIGIDWALL_PLANAR_ID", f10(7) + "wall at x = 0", f10(0), f10(0.0, 0.0, 0.0, 1.0, 0.0, 0.0)]
    lines += ["*INITIAL_VELOCITY", f10(0), f10(-v0, 0.0, 0.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "bar_wall.k"), lines)


def bar_moving_wall(outdir, name, mass_ratio):
    """The bar_wall problem with a *RIGIDWALL_PLANAR_MOVING of mass
    mass_ratio x the bar's, at rest: a heavy wall acts as the fixed one; a
    light one is pushed away and carries kinetic energy."""
    L, a, n = 1.0, 0.005, 200
    E, rho, v0 = 200e9, 7850.0, 10.0
    nodes, hexes = block_mesh(n, 1, 1, L, a, a, origin=(1.0e-6, 0.0, 0.0))
    lines = common(f"elastic bar on a moving rigid wall ({mass_ratio:g} x the bar's mass)", 6.0e-4, 2.0e-6)
    lines += ["*DATABASE_RWFORC", f10(1.0e-6)]
    lines += ["*MAT_ELASTIC", f10(1, rho, E, 0.0)]
    lines += part(1, 1, "bar")
    lines += ["*RIGIDWALL_PLANAR_MOVING", f10(0), f10(0.0, 0.0, 0.0, 1.0, 0.0, 0.0), f10(mass_ratio * rho * L * a * a, 0.0)]
    lines += ["*INITIAL_VELOCITY", f10(0), f10(-v0, 0.0, 0.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", name + ".k"), lines)


def bar_on_pole(outdir):
    """A square bar sliding sideways into a fixed pole (*RIGIDWALL_GEOMETRIC_CYLINDER
    along z): no node may end inside the pole."""
    nodes, hexes = block_mesh(20, 2, 2, 0.2, 0.02, 0.02, origin=(-0.1, 0.0101, 0.0))
    lines = common("bar striking a rigid pole sideways", 4.0e-3, 2.0e-5)
    lines += ["*DATABASE_NODOUT", f10(2.0e-5), "*DATABASE_HISTORY_NODE"]
    front = [k for k, x in sorted(nodes.items()) if abs(x[1] - 0.0101) < 1e-9]
    lines += ["".join(f"{h:10d}" for h in front[i:i + 8]) for i in range(0, len(front), 8)]
    lines += ["*MAT_ELASTIC", f10(1, 2700.0, 70e9, 0.3)]
    lines += part(1, 1, "bar")
    lines += ["*RIGIDWALL_GEOMETRIC_CYLINDER", f10(0), f10(0.0, -0.0, -0.05, 0.0, 0.0, 0.05, 0.0), f10(0.01, 0.1, 0)]
    lines += ["*INITIAL_VELOCITY", f10(0), f10(0.0, -20.0, 0.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "bar_on_pole.k"), lines)


def gravity_drop(outdir):
    """A block falling from rest under *LOAD_BODY_Z onto a planar wall:
    it arrives at sqrt(2 g h)."""
    h, g = 0.5, 9.81
    nodes, hexes = block_mesh(2, 2, 2, 0.1, 0.1, 0.1, origin=(0.0, 0.0, h))
    lines = common("block dropped under gravity onto a planar rigid wall", 0.34, 1.0e-3)
    lines[lines.index("*DATABASE_GLSTAT") + 1] = f10(1.0e-3)
    bottom = [n for n, x in sorted(nodes.items()) if x[2] == h and x[0] == 0.0 and x[1] == 0.0]
    lines += ["*DATABASE_NODOUT", f10(2.0e-4), "*DATABASE_HISTORY_NODE", f10(bottom[0])]
    lines += ["*DATABASE_RWFORC", f10(1.0e-4)]
    lines += ["*MAT_ELASTIC", f10(1, 2700.0, 70e9, 0.3)]
    lines += part(1, 1, "block")
    lines += ["*DEFINE_CURVE_TITLE", "gravity", f10(5), f"{0.0:20.8e}{g:20.8e}", f"{10.0:20.8e}{g:20.8e}"]
    lines += ["*LOAD_BODY_Z", f10(5, 1.0)]
    lines += ["*RIGIDWALL_PLANAR", f10(0), f10(0.0, 0.0, 0.0, 0.0, 0.0, 1.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "gravity_drop.k"), lines)


def tension(outdir, name, title, mat_cards, motion, endtim):
    """One hexahedron (10 mm cube) under uniaxial stress: symmetry SPCs on
    three faces, the top face driven in z by `motion` (cards of a
    *BOUNDARY_PRESCRIBED_MOTION_SET and its curves). History of the top
    nodes: their accelerations give the stress (sigma = -sum m a_z / A)."""
    h = 0.01
    nodes, hexes = block_mesh(1, 1, 1, h, h, h)
    lines = common(title, endtim, endtim / 200)
    top = nodes_where(nodes, lambda x, y, z: z == h)
    lines += ["*DATABASE_NODOUT", f10(endtim / 200), "*DATABASE_HISTORY_NODE", "".join(f"{n:10d}" for n in top)]
    lines += mat_cards
    lines += part(1, 1, "cube")
    lines += node_set(1, nodes_where(nodes, lambda x, y, z: z == 0.0))
    lines += node_set(2, nodes_where(nodes, lambda x, y, z: x == 0.0))
    lines += node_set(3, nodes_where(nodes, lambda x, y, z: y == 0.0))
    lines += node_set(4, top)
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 0, 0, 1), f10(2, 0, 1, 0, 0), f10(3, 0, 0, 1, 0)]
    lines += motion
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", name + ".k"), lines)


def ramp_velocity(v, t_ramp, t_end):
    """Velocity curve 10 on set 4: ramps to v over t_ramp, then holds."""
    return ["*BOUNDARY_PRESCRIBED_MOTION_SET", f10(4, 3, 0, 10, 1.0),
            "*DEFINE_CURVE", f10(10), f"{0.0:20.8e}{0.0:20.8e}", f"{t_ramp:20.8e}{v:20.8e}",
            f"{t_end:20.8e}{v:20.8e}"]


def tension_decks(outdir):
    """Uniaxial stress paths with known answers (steel, E 200 GPa, nu 0.3,
    yield 250 MPa): bilinear isotropic; kinematic with a load reversal;
    a tabulated hardening curve; Cowper-Symonds rate scaling."""
    steel = (7850.0, 200e9, 0.3)
    tension(outdir, "tension_mat003_iso", "uniaxial tension, *MAT_PLASTIC_KINEMATIC isotropic",
            ["*MAT_PLASTIC_KINEMATIC", f10(1, *steel, 250e6, 2e9, 1.0), f10(0.0, 0.0, 0.0, 0.0)],
            ramp_velocity(0.1, 2e-4, 1.0), 5e-3)
    reversal = ["*BOUNDARY_PRESCRIBED_MOTION_SET", f10(4, 3, 2, 11, 1.0),
                "*DEFINE_CURVE", f10(11), f"{0.0:20.8e}{0.0:20.8e}", f"{3e-3:20.8e}{3e-4:20.8e}",
                f"{9e-3:20.8e}{-3e-4:20.8e}"]
    for beta, tag in ((0.0, "kin"), (1.0, "iso_rev")):
        tension(outdir, f"tension_mat003_{tag}", f"uniaxial tension and reversal, *MAT_003 BETA {beta:g}",
                ["*MAT_PLASTIC_KINEMATIC", f10(1, *steel, 250e6, 2e9, beta)], reversal, 8e-3)
    tension(outdir, "tension_mat024_curve", "uniaxial tension, *MAT_PIECEWISE_LINEAR_PLASTICITY with LCSS",
            ["*MAT_PIECEWISE_LINEAR_PLASTICITY", f10(1, *steel, 0.0, 0.0, 0.0, 0.0), f10(0.0, 0.0, 20),
             "*DEFINE_CURVE_TITLE", "yield stress against effective plastic strain", f10(20),
             f"{0.0:20.8e}{250e6:20.8e}", f"{0.01:20.8e}{300e6:20.8e}", f"{0.03:20.8e}{330e6:20.8e}",
             f"{0.1:20.8e}{360e6:20.8e}"],
            ramp_velocity(0.1, 2e-4, 1.0), 5e-3)
    tension(outdir, "tension_mat024_rate", "uniaxial tension at 100/s, *MAT_024 with Cowper-Symonds C 40 P 5",
            ["*MAT_PIECEWISE_LINEAR_PLASTICITY", f10(1, *steel, 250e6, 2e9), f10(40.0, 5.0)],
            ramp_velocity(1.0, 2e-5, 1.0), 4e-4)


def quarter_disk(R, n, m):
    """Quarter disk of radius R (x, y >= 0) as a butterfly mesh: an n x n
    core square of side 0.55 R and two n x m blocks out to the arc.
    Returns points {key: (x, y)} and quads [(k1, k2, k3, k4)] counter-clockwise."""
    c = 0.55 * R
    pts, keys = {}, {}
    def key(x, y):
        k = (round(x / R, 9), round(y / R, 9))
        if k not in keys:
            keys[k] = len(keys) + 1
            pts[keys[k]] = (x, y)
        return keys[k]
    quads = []
    core = [[key(c * i / n, c * j / n) for j in range(n + 1)] for i in range(n + 1)]
    for i in range(n):
        for j in range(n):
            quads.append((core[i][j], core[i + 1][j], core[i + 1][j + 1], core[i][j + 1]))
    # block A: core edge x = c (y = c j/n) to the arc at theta = pi/4 j/n
    # block B: core edge y = c (x = c j/n) to the arc at theta = pi/2 - pi/4 j/n
    for side in (0, 1):
        grid = []
        for j in range(n + 1):
            th = math.pi / 4 * j / n
            if side == 0:
                inner, outer = (c, c * j / n), (R * math.cos(th), R * math.sin(th))
            else:
                inner, outer = (c * j / n, c), (R * math.sin(th), R * math.cos(th))
            grid.append([key(inner[0] + (outer[0] - inner[0]) * r / m, inner[1] + (outer[1] - inner[1]) * r / m)
                         for r in range(m + 1)])
        for j in range(n):
            for r in range(m):
                q = (grid[j][r], grid[j][r + 1], grid[j + 1][r + 1], grid[j + 1][r])
                quads.append(q if side == 0 else (q[0], q[3], q[2], q[1]))
    return pts, quads


def taylor_bar(outdir, name, n, m, nz):
    """Taylor bar (copper, L0 32.4 mm, D0 6.4 mm, 227 m/s onto a frictionless
    rigid wall, 80 us), quarter model on symmetry planes. Reference: final
    length 21.45 mm, foot radius 7.2 mm (issue 3)."""
    R, L = 3.2e-3, 32.4e-3
    pts, quads = quarter_disk(R, n, m)
    np_ = len(pts)
    nodes = {}
    for k in range(nz + 1):
        for pid, (x, y) in pts.items():
            nodes[pid + k * np_] = (x, y, L * k / nz)
    hexes = []
    e = 1
    for k in range(nz):
        for q in quads:
            hexes.append((e, *[v + k * np_ for v in q], *[v + (k + 1) * np_ for v in q]))
            e += 1
    lines = common(f"Taylor bar, copper at 227 m/s, quarter model {len(hexes)} hexahedra", 8.0e-5, 1.0e-6)
    top = [i for i, x in nodes.items() if abs(x[0]) < 1e-12 and abs(x[1]) < 1e-12 and abs(x[2] - L) < 1e-12]
    rim = [i for i, x in sorted(nodes.items()) if abs(x[2]) < 1e-12 and abs(math.hypot(x[0], x[1]) - R) < 1e-9]
    hist = top + rim
    lines += ["*DATABASE_NODOUT", f10(1.0e-6), "*DATABASE_HISTORY_NODE"]
    lines += ["".join(f"{h:10d}" for h in hist[i:i + 8]) for i in range(0, len(hist), 8)]
    lines += ["*MAT_PLASTIC_KINEMATIC", f10(1, 8930.0, 117e9, 0.35, 400e6, 100e6, 1.0)]
    lines += part(1, 1, "copper bar")
    lines += node_set(1, nodes_where(nodes, lambda x, y, z: abs(x) < 1e-12))
    lines += node_set(2, nodes_where(nodes, lambda x, y, z: abs(y) < 1e-12))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 0, 0), f10(2, 0, 0, 1, 0)]
    lines += ["*RIGIDWALL_PLANAR", f10(0), f10(0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0)]
    lines += ["*INITIAL_VELOCITY", f10(0), f10(0.0, 0.0, -227.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", name + ".k"), lines)


def rigid_spin(outdir):
    """A free *MAT_RIGID block spinning about a non-principal axis while it
    translates: no torque, so its energy and angular momentum are constant."""
    nodes, hexes = block_mesh(4, 2, 1, 0.2, 0.1, 0.05)
    lines = common("rigid block, torque-free spin about a non-principal axis", 1.0, 1.0e-3)
    lines[lines.index("*CONTROL_TIMESTEP") + 1] = f10(2.0e-5, 0.9)
    lines += ["*MAT_RIGID", f10(1, 7850.0, 210e9, 0.3)]
    lines += part(1, 1, "rigid block")
    lines += ["*INITIAL_VELOCITY_GENERATION", f10(1, 2, 10.0, 1.0, 0.0, 0.0, 0, 0),
              f10(0.1, 0.05, 0.025, 1.0, 2.0, 3.0, 0, 0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "rigid_spin.k"), lines)


def rigid_block_wall(outdir, name, tilt):
    """A *MAT_RIGID block (0.1 x 0.06 x 0.04 m, 4 x 3 x 2 hexahedra) falling
    at 10 m/s onto a planar rigid wall at z = 0, its mesh turned by tilt[0]
    about x and tilt[1] about y degrees (0, 0: the face lands flat; tilted:
    a corner lands first and the body turns). The wall stops its nodes by
    impulses on the body; every node's history is written."""
    nodes, hexes = block_mesh(4, 3, 2, 0.1, 0.06, 0.04, origin=(-0.05, -0.03, -0.02))
    ax, ay = (math.radians(t) for t in tilt)
    out = {}
    for k, (x, y, z) in nodes.items():
        y, z = y * math.cos(ax) - z * math.sin(ax), y * math.sin(ax) + z * math.cos(ax)
        x, z = x * math.cos(ay) + z * math.sin(ay), -x * math.sin(ay) + z * math.cos(ay)
        out[k] = (x, y, z)
    zmin = min(z for _, _, z in out.values())
    nodes = {k: (x, y, z - zmin + 1.0e-3) for k, (x, y, z) in out.items()}
    lines = common("rigid block on a planar rigid wall", 0.02, 1.0e-4)
    lines[lines.index("*CONTROL_TIMESTEP") + 1] = f10(1.0e-5, 0.9)
    lines += ["*MAT_RIGID", f10(1, 7850.0, 210e9, 0.3)] + part(1, 1, "rigid block")
    lines += ["*RIGIDWALL_PLANAR", f10(0), f10(0.0, 0.0, 0.0, 0.0, 0.0, 1.0)]
    lines += ["*INITIAL_VELOCITY", f10(0), f10(0.0, 0.0, -10.0)]
    lines += node_set(1, sorted(nodes)) + ["*DATABASE_NODOUT", f10(1.0e-4), "*DATABASE_HISTORY_NODE_SET", f10(1)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", name + ".k"), lines)


def rigid_shell_spin(outdir):
    """A *MAT_RIGID plate of shells (0.2 x 0.1 m, 2 mm) spinning torque-free
    about a non-principal axis: inertia from the shells (with the thickness
    term), energy and angular momentum kept."""
    a, b, t, nx, ny = 0.2, 0.1, 0.002, 4, 2
    nodes = {1 + i + (nx + 1) * j: (a * i / nx, b * j / ny, 0.0) for j in range(ny + 1) for i in range(nx + 1)}
    lines = common("rigid shell plate, torque-free spin", 0.5, 1.0e-3)
    lines[lines.index("*CONTROL_TIMESTEP") + 1] = f10(2.0e-5, 0.9)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 2), f10(t, t, t, t)]
    lines += ["*MAT_RIGID", f10(1, 7850.0, 210e9, 0.3)]
    lines += ["*PART", "rigid plate", f10(1, 2, 1)]
    lines += ["*INITIAL_VELOCITY_GENERATION", f10(1, 2, 10.0, 1.0, 0.0, 0.0, 0, 0),
              f10(a / 2, b / 2, 0.0, 1.0, 2.0, 3.0, 0, 0)]
    lines += node_cards(nodes) + grid_shell_cards(nx, ny)
    write(os.path.join(outdir, "verify", "rigid_shell_spin.k"), lines)


def shell_warped_spin(outdir):
    """A strongly warped patch of 2 x 2 Belytschko-Tsay shells (20 mm
    square, the nodes 1 mm above and below its mean plane in a checkerboard,
    elastic steel, 2 mm) spinning free at 100 rad/s about an in-plane axis
    through its centre, for a quarter turn: a rigid motion, so the
    hourglass energy must stay nil (the membrane hourglass rates once took
    the warped nodes' in-plane velocities as an hourglass mode). A lone
    spinning element is not used: its breathing mode is above the shell
    time step at TSSFAC 0.9, see doc/theory.md."""
    n, h, w, t = 2, 0.02, 0.001, 0.002
    nodes = {1 + i + (n + 1) * j: (h * i / n, h * j / n, w if (i + j) % 2 == 0 else -w)
             for j in range(n + 1) for i in range(n + 1)}
    lines = common("a warped shell patch spinning free about an in-plane axis", 0.0157, 1.0e-4)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 2), f10(t, t, t, t)]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3)]
    lines += ["*PART", "warped patch", f10(1, 2, 1)]
    lines += ["*INITIAL_VELOCITY_GENERATION", f10(1, 2, 100.0, 0.0, 0.0, 0.0, 0, 0),
              f10(h / 2, h / 2, 0.0, 1.0, 0.0, 0.0, 0, 0)]
    lines += node_cards(nodes) + grid_shell_cards(n, n)
    write(os.path.join(outdir, "verify", "shell_warped_spin.k"), lines)


def rod_with_rigid_mass(outdir):
    """An elastic rod (nu = 0) clamped at x = 0 carrying a rigid mass at its
    free end, set moving along the rod: it vibrates at omega = beta c / L with
    beta tan(beta) = m_rod / M (rod with an end mass)."""
    L, a, n = 1.0, 0.01, 20
    nodes, hexes = block_mesh(n, 1, 1, L, a, a)
    tip = block_mesh(1, 1, 1, 0.1, a, a, origin=(L, 0.0, 0.0), nid0=10001, eid0=1001)
    # the mass block shares the rod's end face
    merge = {}
    for tid, (x, y, z) in tip[0].items():
        for nid, (x2, y2, z2) in nodes.items():
            if abs(x - x2) < 1e-12 and abs(y - y2) < 1e-12 and abs(z - z2) < 1e-12:
                merge[tid] = nid
    tip_nodes = {k: v for k, v in tip[0].items() if k not in merge}
    tip_hex = [(h[0], *[merge.get(v, v) for v in h[1:]]) for h in tip[1]]
    lines = common("elastic rod with a rigid end mass (vibration frequency)", 1.0e-2, 1.0e-5)
    probe = [k for k, x in tip_nodes.items()][0]
    lines += ["*DATABASE_NODOUT", f10(1.0e-5), "*DATABASE_HISTORY_NODE", f10(probe)]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.0)]
    lines += ["*MAT_RIGID", f10(2, 1.0e6, 200e9, 0.3), f10(1.0, 0, 6)]
    lines += part(1, 1, "rod") + part(2, 2, "rigid end mass")
    lines += node_set(1, nodes_where(nodes, lambda x, y, z: x == 0.0))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 0, 0, 0)]
    lines += ["*INITIAL_VELOCITY_GENERATION", f10(2, 2, 0.0, 1.0, 0.0, 0.0, 0, 0), f10(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0, 0)]
    all_nodes = dict(nodes)
    all_nodes.update(tip_nodes)
    lines += node_cards(all_nodes) + solid_cards(hexes, 1) + solid_cards(tip_hex, 2)
    write(os.path.join(outdir, "verify", "rod_rigid_mass.k"), lines)


def rigid_prescribed(outdir):
    """A *MAT_RIGID block driven by *BOUNDARY_PRESCRIBED_MOTION_RIGID: x
    displacement u(t) = 0.01 sin(pi t / 0.02) ... given as a curve, and a spin
    of 2 rad/s about z. Opposite corners give the centre and the angle."""
    nodes, hexes = block_mesh(2, 2, 2, 0.1, 0.1, 0.1)
    lines = common("rigid block following prescribed translation and spin", 0.02, 2.0e-4)
    lines[lines.index("*CONTROL_TIMESTEP") + 1] = f10(1.0e-5, 0.9)
    c1 = [n for n, x in nodes.items() if x == (0.0, 0.0, 0.0)][0]
    c2 = [n for n, x in nodes.items() if x == (0.1, 0.1, 0.0)][0]
    lines += ["*DATABASE_NODOUT", f10(2.0e-4), "*DATABASE_HISTORY_NODE", f10(c1, c2)]
    lines += ["*MAT_RIGID", f10(1, 7850.0, 210e9, 0.3)]
    lines += part(1, 1, "driven block")
    lines += ["*DEFINE_CURVE", f10(30)] + [f"{t:20.8e}{0.01 * math.sin(math.pi * t / 0.02):20.8e}"
                                         for t in [i * 0.0005 for i in range(41)]]
    lines += ["*DEFINE_CURVE", f10(31), f"{0.0:20.8e}{2.0:20.8e}", f"{1.0:20.8e}{2.0:20.8e}"]
    lines += ["*BOUNDARY_PRESCRIBED_MOTION_RIGID", f10(1, 1, 2, 30, 1.0), f10(1, 7, 0, 31, 1.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "rigid_prescribed.k"), lines)


def spot_weld(outdir, name, tfail):
    """Two elastic plates, 2 mm apart, joined by four spot welds (node pairs
    across the gap); the lower one starts sliding at 10 m/s. With no failure
    they move as one at 5 m/s; welds that fail at once leave the upper plate
    behind."""
    A = block_mesh(4, 4, 1, 0.1, 0.1, 0.01)
    B = block_mesh(4, 4, 1, 0.1, 0.1, 0.01, origin=(0.0, 0.0, 0.012), nid0=1001, eid0=1001)
    lines = common(f"two plates joined by spot welds (TFAIL {tfail:g})", 2.0e-3, 2.0e-5)
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 210e9, 0.3)]
    lines += part(1, 1, "lower plate") + part(2, 1, "upper plate")
    sid = 10
    for (x, y) in ((0.025, 0.025), (0.075, 0.025), (0.025, 0.075), (0.075, 0.075)):
        a = [n for n, p in A[0].items() if abs(p[0] - x) < 1e-9 and abs(p[1] - y) < 1e-9 and abs(p[2] - 0.01) < 1e-9]
        b = [n for n, p in B[0].items() if abs(p[0] - x) < 1e-9 and abs(p[1] - y) < 1e-9 and abs(p[2] - 0.012) < 1e-9]
        lines += node_set(sid, a + b)
        lines += ["*CONSTRAINED_GENERALIZED_WELD_SPOT", f10(sid), f10(tfail)]
        sid += 1
    lines += ["*INITIAL_VELOCITY_GENERATION", f10(1, 2, 0.0, 10.0, 0.0, 0.0, 0, 0), f10(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)]
    lines += ["*DATABASE_NODOUT", f10(2.0e-5)]
    nodes = dict(A[0]); nodes.update(B[0])
    lines += node_cards(nodes) + solid_cards(A[1], 1) + solid_cards(B[1], 2)
    write(os.path.join(outdir, "verify", name + ".k"), lines)


def pressure_column(outdir):
    """A column (nu = 0.3) on symmetry planes loaded on its top face by a
    pressure ramped slowly to 100 MPa (*LOAD_SEGMENT_SET): uniaxial stress, the
    top moves down by p L / E."""
    n, a, L = 2, 0.02, 0.1
    nodes, hexes = block_mesh(n, n, 5 * n, a, a, L)
    lines = common("column under a slowly ramped top pressure", 2.0e-3, 2.0e-5)
    top = [k for k, x in sorted(nodes.items()) if abs(x[2] - L) < 1e-12]
    lines += ["*DATABASE_NODOUT", f10(2.0e-5), "*DATABASE_HISTORY_NODE", f10(top[0])]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3)]
    lines += part(1, 1, "column")
    lines += node_set(1, nodes_where(nodes, lambda x, y, z: z == 0.0))
    lines += node_set(2, nodes_where(nodes, lambda x, y, z: x == 0.0))
    lines += node_set(3, nodes_where(nodes, lambda x, y, z: y == 0.0))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 0, 0, 1), f10(2, 0, 1, 0, 0), f10(3, 0, 0, 1, 0)]
    segs = [h for h in hexes if all(abs(nodes[v][2] - L) < 1e-12 for v in h[5:9])]
    lines += ["*SET_SEGMENT", f10(1)] + ["".join(f"{v:10d}" for v in h[5:9]) for h in segs]
    lines += ["*DEFINE_CURVE", f10(40), f"{0.0:20.8e}{0.0:20.8e}", f"{1.5e-3:20.8e}{1.0e8:20.8e}",
              f"{1.0:20.8e}{1.0e8:20.8e}"]
    lines += ["*LOAD_SEGMENT_SET", f10(1, 40, 1.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "verify", "pressure_column.k"), lines)


def shell_cantilever(outdir, nx=20, name="shell_cantilever"):
    """A cantilever strip of Belytschko-Tsay shells (nu = 0, nx along its
    length), clamped at x = 0, released from the first mode's velocity
    shape: it vibrates at the beam's first frequency
    f1 = (1.875^2 / 2 pi) sqrt(E t^2 / (12 rho L^4))."""
    L, b, t, ny = 0.2, 0.02, 0.002, 2
    E, rho = 200e9, 7850.0
    nodes = {}
    for j in range(ny + 1):
        for i in range(nx + 1):
            nodes[1 + i + (nx + 1) * j] = (L * i / nx, b * j / ny, 0.0)
    shells = []
    e = 1
    for j in range(ny):
        for i in range(nx):
            n1 = 1 + i + (nx + 1) * j
            shells.append((e, n1, n1 + 1, n1 + 1 + nx + 1, n1 + nx + 1))
            e += 1
    lines = common("cantilever strip of Belytschko-Tsay shells (first bending frequency)", 0.06, 2.0e-4)
    tip = [k for k, x in nodes.items() if abs(x[0] - L) < 1e-12 and x[1] == 0.0][0]
    lines += ["*DATABASE_NODOUT", f10(2.0e-4), "*DATABASE_HISTORY_NODE", f10(tip)]
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 3), f10(t, t, t, t)]
    lines += ["*MAT_ELASTIC", f10(1, rho, E, 0.0)]
    lines += ["*PART", "strip", f10(1, 2, 1)]
    lines += node_set(1, nodes_where(nodes, lambda x, y, z: x == 0.0))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 1, 1, 1)]
    # first cantilever mode: w(x) ~ (cosh - cos) - s (sinh - sin), s = 0.7341
    bl = 1.8751
    def mode(x):
        k = bl * x / L
        return (math.cosh(k) - math.cos(k)) - 0.7341 * (math.sinh(k) - math.sin(k))
    def slope(x):
        k = bl * x / L
        return bl / L * ((math.sinh(k) + math.sin(k)) - 0.7341 * (math.cosh(k) - math.cos(k)))
    amp = 0.05 / mode(L)
    lines += ["*INITIAL_VELOCITY_NODE"]
    for n, (x, y, z) in sorted(nodes.items()):
        if x > 0:
            lines.append(f"{n:10d}{0.0:10.4g}{0.0:10.4g}{amp * mode(x):10.4g}{0.0:10.4g}{-amp * slope(x):10.4g}")
    out = ["*NODE"] + [f"{n:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for n, (x, y, z) in sorted(nodes.items())]
    out += ["*ELEMENT_SHELL"] + [f"{s[0]:8d}{1:8d}" + "".join(f"{v:8d}" for v in s[1:]) for s in shells]
    lines += out
    write(os.path.join(outdir, "verify", name + ".k"), lines)


def shell_tension(outdir):
    """One Belytschko-Tsay shell (10 mm square, 1 mm) pulled along x under
    plane stress: the *MAT_PLASTIC_KINEMATIC path of the solid test, with
    the thickness held (so the stress is the force over width x t0)."""
    h, t = 0.01, 0.001
    nodes = {1: (0.0, 0.0, 0.0), 2: (h, 0.0, 0.0), 3: (h, h, 0.0), 4: (0.0, h, 0.0)}
    lines = common("one shell in uniaxial tension, *MAT_PLASTIC_KINEMATIC, plane stress", 5e-3, 2.5e-5)
    lines += ["*DATABASE_NODOUT", f10(2.5e-5), "*DATABASE_HISTORY_NODE", f10(2, 3)]
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 3), f10(t, t, t, t)]
    lines += ["*MAT_PLASTIC_KINEMATIC", f10(1, 7850.0, 200e9, 0.3, 250e6, 2e9, 1.0)]
    lines += ["*PART", "sheet", f10(1, 2, 1)]
    lines += node_set(1, [1, 4]) + node_set(2, [1, 2]) + node_set(3, [2, 3])
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 0, 1, 1, 1, 1), f10(2, 0, 0, 1, 1, 1, 1, 1),
              f10(3, 0, 0, 0, 1, 1, 1, 1)]
    lines += ["*BOUNDARY_PRESCRIBED_MOTION_SET", f10(3, 1, 0, 10, 1.0),
              "*DEFINE_CURVE", f10(10), f"{0.0:20.8e}{0.0:20.8e}", f"{2e-4:20.8e}{0.1:20.8e}", f"{1.0:20.8e}{0.1:20.8e}"]
    lines += ["*NODE"] + [f"{n:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for n, (x, y, z) in sorted(nodes.items())]
    lines += ["*ELEMENT_SHELL", f"{1:8d}{1:8d}{1:8d}{2:8d}{3:8d}{4:8d}"]
    write(os.path.join(outdir, "verify", "shell_tension.k"), lines)


def shell_tension_thick(outdir):
    """shell_tension with *CONTROL_SHELL ISTUPD 1: the thickness follows the
    strain, so the pulling force falls with the thickness."""
    src = os.path.join(outdir, "verify", "shell_tension.k")
    with open(src) as f:
        text = f.read()
    text = text.replace("*SECTION_SHELL", "*CONTROL_SHELL\n" + f10(0.0, 0, 0, 1) + "\n*SECTION_SHELL", 1)
    text = text.replace("one shell in uniaxial tension", "one shell in uniaxial tension, thickness change", 1)
    with open(os.path.join(outdir, "verify", "shell_tension_thick.k"), "w") as f:
        f.write(text)


def shell_tension_tri(outdir):
    """shell_tension meshed as two triangles (N3 = N4) split along the 1-3
    diagonal: uniaxial stress is a linear field, which the one-point
    Belytschko-Tsay strain rate reproduces exactly on a degenerate quad, so
    the path must match the quad's closed form."""
    src = os.path.join(outdir, "verify", "shell_tension.k")
    with open(src) as f:
        text = f.read()
    quad = f"{1:8d}{1:8d}{1:8d}{2:8d}{3:8d}{4:8d}"
    tris = f"{1:8d}{1:8d}{1:8d}{2:8d}{3:8d}{3:8d}\n{2:8d}{1:8d}{1:8d}{3:8d}{4:8d}{4:8d}"
    assert quad in text
    text = text.replace(quad, tris, 1)
    text = text.replace("one shell in uniaxial tension", "two triangular shells in uniaxial tension", 1)
    with open(os.path.join(outdir, "verify", "shell_tension_tri.k"), "w") as f:
        f.write(text)


def clamped_plate(outdir, n=16, name="clamped_plate"):
    """A clamped square steel plate (0.2 m, 2 mm, n x n shells) under a
    small uniform pressure (*LOAD_SHELL_SET) ramped over about four periods
    and held: the centre settles at 0.00126 q a^4 / D (plate theory)."""
    a, t = 0.2, 0.002
    nodes = {}
    for j in range(n + 1):
        for i in range(n + 1):
            nodes[1 + i + (n + 1) * j] = (a * i / n, a * j / n, 0.0)
    shells = []
    e = 1
    for j in range(n):
        for i in range(n):
            n1 = 1 + i + (n + 1) * j
            shells.append((e, n1, n1 + 1, n1 + 1 + n + 1, n1 + n + 1))
            e += 1
    lines = common("clamped square plate under uniform pressure", 0.02, 1.0e-4)
    centre = [k for k, x in nodes.items() if abs(x[0] - a / 2) < 1e-12 and abs(x[1] - a / 2) < 1e-12][0]
    lines += ["*DATABASE_NODOUT", f10(1.0e-4), "*DATABASE_HISTORY_NODE", f10(centre)]
    lines += ["*SECTION_SHELL", f10(2, 2, 0.0, 3), f10(t, t, t, t)]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3)]
    lines += ["*PART", "plate", f10(1, 2, 1)]
    edge = [k for k, x in sorted(nodes.items()) if x[0] in (0.0, a) or x[1] in (0.0, a)]
    lines += node_set(1, edge)
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 1, 1, 1)]
    lines += ["*SET_SHELL_LIST_GENERATE", f10(1), f10(1, len(shells))]
    lines += ["*DEFINE_CURVE", f10(50), f"{0.0:20.8e}{0.0:20.8e}", f"{0.01:20.8e}{1000.0:20.8e}",
              f"{1.0:20.8e}{1000.0:20.8e}"]
    lines += ["*LOAD_SHELL_SET", f10(1, 50, 1.0)]
    lines += ["*NODE"] + [f"{k:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for k, (x, y, z) in sorted(nodes.items())]
    lines += ["*ELEMENT_SHELL"] + [f"{s[0]:8d}{1:8d}" + "".join(f"{v:8d}" for v in s[1:]) for s in shells]
    write(os.path.join(outdir, "verify", name + ".k"), lines)


def mixed_deck(outdir, gravity=False):
    """Solids, shells and a rigid part in one deck: a steel block (solids)
    with a shell plate on its top face and a rigid block under it, both
    sharing nodes with the block.  Only the rigid block starts moving, so it
    pulls the elastic block and the plate after it: the deck deforms, and its
    energy and momentum checks mean something.  Also used to check the log's
    subsystem list."""
    blk = block_mesh(2, 2, 2, 0.1, 0.1, 0.1)
    rig = block_mesh(2, 2, 1, 0.1, 0.1, 0.05, origin=(0.0, 0.0, -0.05), nid0=501, eid0=501)
    bottom = {(round(x[0], 6), round(x[1], 6)): k for k, x in blk[0].items() if abs(x[2]) < 1e-12}
    remap = {k: bottom[(round(x[0], 6), round(x[1], 6))] for k, x in rig[0].items() if abs(x[2]) < 1e-12}
    nodes = dict(blk[0])
    nodes.update({k: x for k, x in rig[0].items() if k not in remap})
    rig_elems = [(e[0], *[remap.get(n, n) for n in e[1:]]) for e in rig[1]]
    grid = {(round(x[0], 6), round(x[1], 6)): k for k, x in blk[0].items() if abs(x[2] - 0.1) < 1e-12}
    xs = sorted({k[0] for k in grid})
    shells = []
    e = 1001
    for j in range(2):
        for i in range(2):
            c = [grid[(xs[i], xs[j])], grid[(xs[i + 1], xs[j])], grid[(xs[i + 1], xs[j + 1])], grid[(xs[i], xs[j + 1])]]
            shells.append((e, *c))
            e += 1
    title = "solids, shells and a rigid part in one deck" + (", falling under gravity" if gravity else "")
    lines = common(title, 2.0e-3, 1.0e-4)
    lines += ["*CONTROL_SHELL", f10(20.0, 0, 0, 1, 2, 0, 2)]
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 3), f10(0.002, 0.002, 0.002, 0.002)]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3), "*MAT_RIGID", f10(2, 7850.0, 200e9, 0.3)]
    lines += part(1, 1, "solid block") + ["*PART", "top plate", f10(2, 2, 1)] + part(3, 2, "rigid block")
    if gravity:
        # everything starts at rest and falls: no node may lag behind another
        lines += ["*DEFINE_CURVE", f10(5), f"{0.0:20.8e}{9.81:20.8e}", f"{10.0:20.8e}{9.81:20.8e}"]
        lines += ["*LOAD_BODY_Z", f10(5, 1.0)]
    else:
        lines += ["*INITIAL_VELOCITY_GENERATION", f10(3, 2, 0.0, 0.0, 0.0, -2.0), f10(0.0, 0.0, 0.0)]
    lines += node_cards(nodes) + solid_cards(blk[1], 1) + solid_cards(rig_elems, 3)
    lines += ["*ELEMENT_SHELL"] + [f"{s[0]:8d}{2:8d}" + "".join(f"{v:8d}" for v in s[1:]) for s in shells]
    name = "mixed_solid_shell_rigid_gravity.k" if gravity else "mixed_solid_shell_rigid.k"
    write(os.path.join(outdir, "verify", name), lines)


def contact_block_plate(outdir, name, contact, xcontact=None, endtim=2.25e-3):
    """A 0.2 m steel cube (2x2x2 hexahedra, part 1) flying at 200 m/s down
    onto a 1 m square plate of 10x10 shells 10 mm thick (part 2) 0.3 m
    below it, with the given contact cards. The decks test the global
    search (when the plate enters the cube's master node lists); at 200 m/s
    the default penalty cannot stop the cube in the thin plate (its nodes
    cross the mid-surface within a few steps), so the impact itself is no
    physics test. Node set 90 (the centre of the cube's lower face) is dumped."""
    blk, hexes = block_mesh(2, 2, 2, 0.2, 0.2, 0.2, origin=(0.4, 0.4, 0.3))
    n = 10
    pid = lambda i, j: 1001 + i + (n + 1) * j
    lines = common(f"contact steps 1-2: cube over a plate ({name})", endtim, 1.0e-4)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 2), f10(0.01, 0.01, 0.01, 0.01)]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3)]
    lines += part(1, 1, "cube") + ["*PART", "plate", f10(2, 2, 1)]
    lines += node_set(1, sorted(blk))
    lines += ["*INITIAL_VELOCITY", f10(1), f10(0.0, 0.0, -200.0)]
    lines += node_set(90, nodes_where(blk, lambda x, y, z: abs(x - 0.5) < 1e-9 and abs(y - 0.5) < 1e-9
                                      and abs(z - 0.3) < 1e-9))
    lines += node_set(91, nodes_where(blk, lambda x, y, z: abs(z - 0.3) < 1e-9))
    lines += ["*SET_PART_LIST", f10(5), f10(1)]
    low = {(round(x, 6), round(y, 6)): k for k, (x, y, z) in blk.items() if abs(z - 0.3) < 1e-9}
    xs = sorted({k[0] for k in low})
    lines += ["*SET_SEGMENT", f10(8)]
    for j in range(2):
        for i in range(2):  # the cube's lower faces, written in either node order
            q = [low[(xs[i], xs[j])], low[(xs[i + 1], xs[j])], low[(xs[i + 1], xs[j + 1])], low[(xs[i], xs[j + 1])]]
            lines.append(f10(*(q if (i + j) % 2 else q[::-1])))
    lines += ["*SET_SHELL_LIST_GENERATE", f10(9), f10(1001, 1100)]
    lines += contact
    if xcontact:
        lines += ["*CONTROL_XDYNA_CONTACT", xcontact]
    lines += node_cards(blk) + solid_cards(hexes, 1)
    lines += ["*NODE"] + [f"{pid(i, j):8d}{i / n:16.9e}{j / n:16.9e}{0.0:16.9e}{0:8d}{0:8d}"
                          for j in range(n + 1) for i in range(n + 1)]
    lines += ["*ELEMENT_SHELL"] + [f"{1001 + i + n * j:8d}{2:8d}{pid(i, j):8d}{pid(i + 1, j):8d}"
                                   f"{pid(i + 1, j + 1):8d}{pid(i, j + 1):8d}" for j in range(n) for i in range(n)]
    write(os.path.join(outdir, "contact", name + ".k"), lines)


def contact_two_bars(outdir, name="two_bars_penalty", xcontact=None, n=20, slsfac=None):
    """Two identical elastic bars (nu = 0, 100 mm, n elements) 0.1 mm
    apart, meeting head-on at 5 m/s each through a whole-model single-surface
    contact: they touch for 2L/c = 39.6 us and leave with their velocities
    reversed (1-D elastic impact of equal bars). The committed deck has 40
    elements and SLSFAC 1: with the default 0.1 the interface spring is
    about as stiff as the bar itself and the contact lasts 61% longer."""
    L, a, gap, v0 = 0.1, 0.01, 1.0e-4, 5.0
    A = block_mesh(n, 1, 1, L, a, a)
    B = block_mesh(n, 1, 1, L, a, a, origin=(L + gap, 0.0, 0.0), nid0=1001, eid0=1001)
    lines = common("two elastic bars meeting head-on through contact", 1.0e-4, 1.0e-6)
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.0)]
    lines += part(1, 1, "left bar") + part(2, 1, "right bar")
    lines += node_set(1, sorted(A[0])) + node_set(2, sorted(B[0]))
    lines += ["*INITIAL_VELOCITY", f10(1), f10(v0, 0.0, 0.0), "*INITIAL_VELOCITY", f10(2), f10(-v0, 0.0, 0.0)]
    fa = nodes_where(A[0], lambda x, y, z: abs(x - L) < 1e-12 and y == 0.0 and z == 0.0)
    fb = nodes_where(B[0], lambda x, y, z: abs(x - L - gap) < 1e-12 and y == 0.0 and z == 0.0)
    lines += ["*DATABASE_NODOUT", f10(2.0e-7), "*DATABASE_HISTORY_NODE", f10(fa[0], fb[0])]
    lines += ["*DATABASE_RCFORC", f10(2.0e-7)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    if slsfac:
        lines += ["*CONTROL_CONTACT", f10(slsfac)]
    if xcontact:
        lines += ["*CONTROL_XDYNA_CONTACT", xcontact]
    lines += node_cards({**A[0], **B[0]}) + solid_cards(A[1], 1) + solid_cards(B[1], 2)
    write(os.path.join(outdir, "contact", name + ".k"), lines)


def contact_block_on_block(outdir, name="block_on_block", xcontact=None):
    """A 0.1 m steel cube (3x3x3) resting under gravity on a fixed 0.2 m
    plate-like block (4x4x2) with its own nodes, both solid, whole-model
    single-surface contact. Static penetration m g / (9 k) is tiny; the
    test asks for under 1% of the solid thickness."""
    lower = block_mesh(4, 4, 2, 0.2, 0.2, 0.05, origin=(-0.05, -0.05, -0.05))
    upper = block_mesh(3, 3, 3, 0.1, 0.1, 0.1, nid0=1001, eid0=1001)
    lines = common("a block resting on a block under gravity", 0.02, 2.0e-4)
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3)]
    lines += part(1, 1, "lower block") + part(2, 1, "upper block")
    lines += node_set(1, nodes_where(lower[0], lambda x, y, z: abs(z + 0.05) < 1e-12))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1)]
    lines += ["*DEFINE_CURVE", f10(5), f"{0.0:20.8e}{9.81:20.8e}", f"{10.0:20.8e}{9.81:20.8e}"]
    lines += ["*LOAD_BODY_Z", f10(5, 1.0)]
    bottom = nodes_where(upper[0], lambda x, y, z: z == 0.0)
    lines += ["*DATABASE_NODOUT", f10(2.0e-4), "*DATABASE_HISTORY_NODE"]
    lines += ["".join(f"{k:10d}" for k in bottom[i:i + 8]) for i in range(0, len(bottom), 8)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    if xcontact:
        lines += ["*CONTROL_XDYNA_CONTACT", xcontact]
    lines += node_cards({**lower[0], **upper[0]}) + solid_cards(lower[1], 1) + solid_cards(upper[1], 2)
    write(os.path.join(outdir, "contact", name + ".k"), lines)


def contact_friction(outdir, name, v0, ax):
    """A 50 mm cube (2x2x2, soft elastic: E 10 MPa, rho 1000) on a fixed
    plate-like block, under gravity 9.81 down and `ax` along x (a body load),
    sliding at v0 along x at the start; Coulomb friction FS = FD = 0.3.
    Sliding: the cube decelerates at mu g - ax. Sticking (v0 = 0, ax below
    mu g): it stays put."""
    lower = block_mesh(8, 2, 1, 0.4, 0.1, 0.02, origin=(-0.05, -0.025, -0.02))
    cube = block_mesh(2, 2, 2, 0.05, 0.05, 0.05, origin=(0.0, 0.0, 0.0), nid0=1001, eid0=1001)
    lines = common(f"cube on a plate with Coulomb friction ({name})", 0.05, 1.0e-3)
    lines += ["*MAT_ELASTIC", f10(1, 1000.0, 1.0e7, 0.3)]
    lines += part(1, 1, "plate") + part(2, 1, "cube")
    lines += node_set(1, sorted(lower[0]))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1)]
    lines += node_set(2, sorted(cube[0]))
    if v0:
        lines += ["*INITIAL_VELOCITY", f10(2), f10(v0, 0.0, 0.0)]
    lines += ["*DEFINE_CURVE", f10(5), f"{0.0:20.8e}{9.81:20.8e}", f"{10.0:20.8e}{9.81:20.8e}"]
    lines += ["*LOAD_BODY_Z", f10(5, 1.0)]
    if ax:
        lines += ["*DEFINE_CURVE", f10(6), f"{0.0:20.8e}{-ax:20.8e}", f"{10.0:20.8e}{-ax:20.8e}"]
        lines += ["*LOAD_BODY_X", f10(6, 1.0)]
    lines += ["*DATABASE_RCFORC", f10(1.0e-3)]
    lines += ["*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", f10(2, 1, 3, 3), f10(0.3, 0.3), ""]
    lines += node_cards({**lower[0], **cube[0]}) + solid_cards(lower[1], 1) + solid_cards(cube[1], 2)
    write(os.path.join(outdir, "contact", name + ".k"), lines)


def square_tube(c, t, length, h):
    """Nodes and quadrilateral shells of a square tube (side c, mid-surface)
    along z from 0 to `length`, elements about h: (nodes dict, shells list,
    number of nodes around, number of rows)."""
    nside = max(1, round(c / h))
    nz = max(1, round(length / h))
    around = []
    for side in range(4):
        for k in range(nside):
            s = -c / 2 + c * k / nside
            around.append([(s, -c / 2), (c / 2, s), (-s, c / 2), (-c / 2, -s)][side])
    nring = len(around)
    nodes, shells = {}, []
    for j in range(nz + 1):
        z = length * j / nz
        for i, (x, y) in enumerate(around):
            nodes[1 + i + nring * j] = (x, y, z)
    e = 1
    for j in range(nz):
        for i in range(nring):
            n1 = 1 + i + nring * j
            n2 = 1 + (i + 1) % nring + nring * j
            shells.append((e, n1, n2, n2 + nring, n1 + nring))
            e += 1
    return nodes, shells, nring, nz


def tube_crush(outdir, name="tube_crush", c=0.05, t=0.0015, length=0.15, h=0.005, v=10.0, endtim=6.0e-3,
               history_all=True):
    """A square steel tube (50 mm side, 1.5 mm wall, 150 mm long, 5 mm
    Belytschko-Tsay shells, *MAT_024 with 250 MPa yield and 1 GPa tangent),
    clamped at the bottom and crushed by its top ring driven down at
    10 m/s (prescribed velocity), whole-model single-surface contact. Two
    opposite faces carry a 0.2 mm inward dent near the top, so the first
    fold forms there. Mean crush force against Abramowicz & Jones:
    P = 13.06 sigma0 t^(5/3) C^(1/3) = 23.6 kN for sigma0 = 250 MPa."""
    nodes, shells, nring, nz = square_tube(c, t, length, h)
    # dents: two opposite faces (x = +-c/2), one row below the top quarter
    jd = round(0.8 * nz)
    for k, (x, y, z) in list(nodes.items()):
        if abs(z - length * jd / nz) < 1e-9 and abs(abs(x) - c / 2) < 1e-9 and abs(y) < c / 2 - 1e-9:
            nodes[k] = (x - math.copysign(2.0e-4, x) * math.cos(math.pi * y / c), y, z)
    lines = common(f"square tube crush ({len(shells)} shells)", endtim, endtim / 60)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 5), f10(t, t, t, t)]
    lines += ["*MAT_PIECEWISE_LINEAR_PLASTICITY", f10(1, 7850.0, 200e9, 0.3, 250e6, 1.0e9)]
    lines += ["*PART", "tube", f10(1, 2, 1)]
    bottom = [k for k, x in sorted(nodes.items()) if x[2] == 0.0]
    top = [k for k, x in sorted(nodes.items()) if abs(x[2] - length) < 1e-9]
    lines += node_set(1, bottom) + node_set(2, top)
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 1, 1, 1)]
    lines += ["*DEFINE_CURVE", f10(7), f"{0.0:20.8e}{-v:20.8e}", f"{1.0:20.8e}{-v:20.8e}"]
    lines += ["*BOUNDARY_PRESCRIBED_MOTION_SET", f10(2, 3, 0, 7, 1.0)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    lines += ["*DATABASE_RCFORC", f10(endtim / 60), "*DATABASE_BINARY_D3PLOT", f10(endtim / 12)]
    if history_all:
        lines += node_set(3, sorted(nodes))
        lines += ["*DATABASE_NODOUT", f10(endtim / 60), "*DATABASE_HISTORY_NODE_SET", f10(3)]
    lines += ["*NODE"] + [f"{k:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for k, (x, y, z) in sorted(nodes.items())]
    lines += ["*ELEMENT_SHELL"] + [f"{s[0]:8d}{1:8d}" + "".join(f"{n:8d}" for n in s[1:]) for s in shells]
    write(os.path.join(outdir, "contact", name + ".k"), lines)


def shell_fold(outdir):
    """A steel strip (1 mm, 20 mm wide) bent into a U: a clamped lower leg
    and an upper leg 10 mm above it, 100 mm long, joined by a 10 mm web at
    x = 100 mm; one part, whole-model single-surface contact. A pressure on
    the outer half of the upper leg, ramped to 60 kPa over 10 ms, folds it
    down onto the lower leg: self-contact of shells (two-sided segments,
    half-thickness offsets)."""
    h, w, L, gap, t = 0.005, 0.02, 0.1, 0.01, 0.001
    nx, ny = round(L / h), round(w / h)
    nodes, shells = {}, []
    # a path of points along the strip: lower leg x 0..L, web z 0..gap, upper leg x L..0
    path = [(i * h, 0.0) for i in range(nx + 1)] + [(L, gap * k / 2) for k in (1, 2)] + \
           [(L - i * h, gap) for i in range(1, nx + 1)]
    for i, (x, z) in enumerate(path):
        for j in range(ny + 1):
            nodes[1 + j + (ny + 1) * i] = (x, j * h, z)
    e = 1
    for i in range(len(path) - 1):
        for j in range(ny):
            n1 = 1 + j + (ny + 1) * i
            shells.append((e, n1, n1 + ny + 1, n1 + ny + 2, n1 + 1))
            e += 1
    lines = common("a U-shaped strip folded onto itself by pressure (shell self-contact)", 0.012, 2.0e-4)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 3), f10(t, t, t, t)]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3)]
    lines += ["*PART", "strip", f10(1, 2, 1)]
    lower = [k for k, x in sorted(nodes.items()) if x[2] == 0.0]
    lines += node_set(1, lower) + ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 1, 1, 1)]
    loaded = [s[0] for s in shells if all(nodes[n][2] == gap and nodes[n][0] <= L / 2 + 1e-9 for n in s[1:])]
    lines += ["*SET_SHELL_LIST", f10(2)] + ["".join(f"{k:10d}" for k in loaded[i:i + 8])
                                            for i in range(0, len(loaded), 8)]
    lines += ["*DEFINE_CURVE", f10(5), f"{0.0:20.8e}{0.0:20.8e}", f"{0.01:20.8e}{6.0e4:20.8e}",
              f"{1.0:20.8e}{6.0e4:20.8e}"]
    lines += ["*LOAD_SHELL_SET", f10(2, 5, -1.0)]   # the upper leg's normals point up: push down
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    lines += node_set(3, sorted(nodes))
    lines += ["*DATABASE_NODOUT", f10(2.0e-4), "*DATABASE_HISTORY_NODE_SET", f10(3)]
    lines += ["*NODE"] + [f"{k:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for k, (x, y, z) in sorted(nodes.items())]
    lines += ["*ELEMENT_SHELL"] + [f"{s[0]:8d}{1:8d}" + "".join(f"{n:8d}" for n in s[1:]) for s in shells]
    write(os.path.join(outdir, "contact", "shell_fold.k"), lines)


def shell_on_solid(outdir, name, edge_on, z0=2.0e-3):
    """A 2 mm steel shell plate (40 x 40 mm, 8 x 8 shells, part 2) and a
    fixed steel block (80 x 80 x 20 mm, 8 x 8 x 2 hexahedra, part 1, top at
    z = 0), surface-to-surface contact plate on block. edge_on: the plate
    stands on its lower edge, 2 mm above the block (1 mm from touching with
    its half-thickness), falling at 2 m/s: it must bounce off the block's
    face. Else: it lies flat, its lower surface
    touching the block (mid-surface at z = 1 mm), under gravity: it must
    rest there, its weight carried by the contact."""
    lower = block_mesh(8, 8, 2, 0.08, 0.08, 0.02, origin=(-0.04, -0.04, -0.02))
    n, a, t = 8, 0.04, 0.002
    nodes, shells = {}, []
    for j in range(n + 1):
        for i in range(n + 1):
            if edge_on:
                p = (-a / 2 + a * i / n + 1.3e-3, 1.1e-3, z0 + a * j / n)
            else:
                p = (-a / 2 + a * i / n + 1.3e-3, -a / 2 + a * j / n + 1.1e-3, t / 2)
            nodes[1001 + i + (n + 1) * j] = p
    for j in range(n):
        for i in range(n):
            n1 = 1001 + i + (n + 1) * j
            shells.append((1001 + i + n * j, n1, n1 + 1, n1 + n + 2, n1 + n + 1))
    lines = common(f"shell plate and solid block ({'edge on, falling' if edge_on else 'lying on its face'})",
                   0.002 if edge_on else 0.01, 1.0e-5 if edge_on else 1.0e-4)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 3), f10(t, t, t, t)]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.3)]
    lines += part(1, 1, "block") + ["*PART", "plate", f10(2, 2, 1)]
    lines += node_set(1, nodes_where(lower[0], lambda x, y, z: abs(z + 0.02) < 1e-12))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1)]
    lines += node_set(2, sorted(nodes))
    if edge_on:
        lines += ["*INITIAL_VELOCITY", f10(2), f10(0.0, 0.0, -2.0)]
    else:
        lines += ["*DEFINE_CURVE", f10(5), f"{0.0:20.8e}{9.81:20.8e}", f"{10.0:20.8e}{9.81:20.8e}"]
        lines += ["*LOAD_BODY_Z", f10(5, 1.0)]
    edge = [k for k, x in sorted(nodes.items()) if abs(x[2] - min(v[2] for v in nodes.values())) < 1e-12]
    lines += ["*DATABASE_NODOUT", f10(1.0e-6 if edge_on else 1.0e-4), "*DATABASE_HISTORY_NODE"]
    lines += ["".join(f"{k:10d}" for k in edge[i:i + 8]) for i in range(0, len(edge), 8)]
    lines += ["*DATABASE_RCFORC", f10(1.0e-6 if edge_on else 1.0e-4)]
    # the plate's nodes against the block's faces: rcforc's slave resultant
    # is the force on the plate
    lines += ["*CONTACT_AUTOMATIC_NODES_TO_SURFACE", f10(2, 1, 3, 3), "", ""]
    lines += node_cards({**lower[0], **nodes}) + solid_cards(lower[1], 1)
    lines += ["*ELEMENT_SHELL"] + [f"{s[0]:8d}{2:8d}" + "".join(f"{v:8d}" for v in s[1:]) for s in shells]
    write(os.path.join(outdir, "contact", name + ".k"), lines)


def contact_patch(outdir):
    """Contact patch test: a steel block of 3 x 3 x 2 hexahedra stacked on
    one of 4 x 4 x 2 (non-matching meshes, 0.1 x 0.1 x 0.05 m each, nu = 0,
    edges aligned), the lower one held at its base, a uniform pressure of
    10 MPa ramped on the top over 1 ms (12 periods of the stack's axial
    mode) and held. The interface must pass the pressure on uniformly:
    contact forces at the interface nodes and reactions at the base nodes
    equal to p times each node's tributary area. History nodes: the lower
    block's top (25), the upper block's bottom (16), the base (25)."""
    lower = block_mesh(4, 4, 2, 0.1, 0.1, 0.05, origin=(0.0, 0.0, -0.05))
    upper = block_mesh(3, 3, 2, 0.1, 0.1, 0.05, nid0=1001, eid0=1001)
    lines = common("contact patch test: uniform pressure across a non-matching interface", 1.5e-3, 1.0e-4)
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.0)]
    lines += part(1, 1, "lower block") + part(2, 1, "upper block")
    lines += node_set(1, nodes_where(lower[0], lambda x, y, z: abs(z + 0.05) < 1e-12))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1)]
    top = {(round(x, 6), round(y, 6)): k for k, (x, y, z) in upper[0].items() if abs(z - 0.05) < 1e-12}
    xs = sorted({k[0] for k in top})
    lines += ["*SET_SEGMENT", f10(1)]
    for j in range(3):
        for i in range(3):
            lines.append(f10(top[(xs[i], xs[j])], top[(xs[i + 1], xs[j])], top[(xs[i + 1], xs[j + 1])],
                             top[(xs[i], xs[j + 1])]))
    lines += ["*DEFINE_CURVE", f10(5), f"{0.0:20.8e}{0.0:20.8e}", f"{1.0e-3:20.8e}{1.0e7:20.8e}",
              f"{1.0:20.8e}{1.0e7:20.8e}"]
    lines += ["*LOAD_SEGMENT_SET", f10(1, 5, 1.0)]
    hist = (nodes_where(lower[0], lambda x, y, z: abs(z) < 1e-12)
            + nodes_where(upper[0], lambda x, y, z: abs(z) < 1e-12)
            + nodes_where(lower[0], lambda x, y, z: abs(z + 0.05) < 1e-12))
    lines += ["*DATABASE_NODOUT", f10(2.0e-6), "*DATABASE_HISTORY_NODE"]
    lines += ["".join(f"{k:10d}" for k in hist[i:i + 8]) for i in range(0, len(hist), 8)]
    lines += ["*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", f10(2, 1, 3, 3), "", ""]
    lines += node_cards({**lower[0], **upper[0]}) + solid_cards(lower[1], 1) + solid_cards(upper[1], 2)
    write(os.path.join(outdir, "contact", "patch_test.k"), lines)


def contact_block_impact(outdir, name, keyword):
    """Two free steel blocks with non-matching meshes (3 x 3 x 2 on
    4 x 4 x 2, 0.1 x 0.1 x 0.05 m each, touching), the upper one moving
    down at 1 m/s: a conservative impact through penalty contact, with the
    upper block's edge nodes on the plane of the lower block's side faces
    (the case that must not be taken for a deep tube contact)."""
    lower = block_mesh(4, 4, 2, 0.1, 0.1, 0.05, origin=(0.0, 0.0, -0.05))
    upper = block_mesh(3, 3, 2, 0.1, 0.1, 0.05, nid0=1001, eid0=1001)
    lines = common(f"two blocks, non-matching meshes, impact through {keyword}", 2.0e-4, 2.0e-6)
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 200e9, 0.0)]
    lines += part(1, 1, "lower block") + part(2, 1, "upper block")
    lines += node_set(9, sorted(upper[0]))
    lines += ["*INITIAL_VELOCITY", f10(9), f10(0.0, 0.0, -1.0)]
    lines += ["*" + keyword, f10(2, 1, 3, 3), "", ""]
    lines += node_cards({**lower[0], **upper[0]}) + solid_cards(lower[1], 1) + solid_cards(upper[1], 2)
    write(os.path.join(outdir, "contact", name + ".k"), lines)


def bench_tubes(ntx, nty, path, ncycle):
    """Benchmark: an ntx x nty array of the crushing square tubes of
    tube_crush (1200 shells each), 70 mm apart, all in one whole-model
    single-surface contact, crushed at 20 m/s so that folds and self-contact
    develop within the run's ncycle cycles."""
    base, shells, nring, nz = square_tube(0.05, 0.0015, 0.15, 0.005)
    nodes, elems, top, bottom = {}, [], [], []
    nn, ne = len(base), len(shells)
    for ty in range(nty):
        for tx in range(ntx):
            off = (tx + ntx * ty)
            dx, dy = 0.07 * tx, 0.07 * ty
            for k, (x, y, z) in base.items():
                zz = z
                if abs(z - 0.12) < 1e-9 and abs(abs(x) - 0.025) < 1e-9 and abs(y) < 0.025 - 1e-9:
                    x -= math.copysign(2.0e-4, x) * math.cos(math.pi * y / 0.05)
                nodes[k + off * nn] = (x + dx, y + dy, zz)
                if z == 0.0:
                    bottom.append(k + off * nn)
                if abs(z - 0.15) < 1e-9:
                    top.append(k + off * nn)
            elems += [(e + off * ne, *[n + off * nn for n in c]) for e, *c in shells]
    lines = common(f"benchmark: {ntx}x{nty} crushing tubes, {len(elems)} shells, single-surface contact",
                   1.0, 1.0, endcyc=ncycle)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 5), f10(0.0015, 0.0015, 0.0015, 0.0015)]
    lines += ["*MAT_PIECEWISE_LINEAR_PLASTICITY", f10(1, 7850.0, 200e9, 0.3, 250e6, 1.0e9)]
    lines += ["*PART", "tubes", f10(1, 2, 1)]
    lines += node_set(1, sorted(bottom)) + node_set(2, sorted(top))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 1, 1, 1)]
    lines += ["*DEFINE_CURVE", f10(7), f"{0.0:20.8e}{-20.0:20.8e}", f"{1.0:20.8e}{-20.0:20.8e}"]
    lines += ["*BOUNDARY_PRESCRIBED_MOTION_SET", f10(2, 3, 0, 7, 1.0)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    lines += ["*NODE"] + [f"{k:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for k, (x, y, z) in sorted(nodes.items())]
    lines += ["*ELEMENT_SHELL"] + [f"{s[0]:8d}{1:8d}" + "".join(f"{n:8d}" for n in s[1:]) for s in elems]
    write(path, lines)


def bench_tube_plate(path, endtim=0.012, ncycle=0):
    """Benchmark: the crushing square tube of tube_crush (1200 shells of
    5 mm) crushed over its length by a rigid plate of 22 x 22 shells of
    10 mm (twice the tube's size, 1,684 shells in all) moving down at
    10 m/s from 2 mm above the tube's top; the tube's bottom ring clamped;
    one whole-model single-surface contact holding the plate too (its nodes
    must not find contacts with their own flat plate). 12 ms crushes 120 mm
    of the 150 mm tube (contact thickness 1.5 mm: 0.5 mm apart at the start)."""
    c, t, length, h = 0.05, 0.0015, 0.15, 0.005
    nodes, shells, nring, nz = square_tube(c, t, length, h)
    jd = round(0.8 * nz)
    for k, (x, y, z) in list(nodes.items()):
        if abs(z - length * jd / nz) < 1e-9 and abs(abs(x) - c / 2) < 1e-9 and abs(y) < c / 2 - 1e-9:
            nodes[k] = (x - math.copysign(2.0e-4, x) * math.cos(math.pi * y / c), y, z)
    npl, hp = 22, 0.01
    n0, e0 = len(nodes), len(shells)
    zp = length + 0.002
    pid = {}
    for j in range(npl + 1):
        for i in range(npl + 1):
            pid[i, j] = n0 + 1 + i + (npl + 1) * j
            nodes[pid[i, j]] = (-npl * hp / 2 + i * hp, -npl * hp / 2 + j * hp, zp)
    plate = [(e0 + 1 + i + npl * j, pid[i, j], pid[i + 1, j], pid[i + 1, j + 1], pid[i, j + 1])
             for j in range(npl) for i in range(npl)]
    lines = common(f"benchmark: square tube ({len(shells)} shells) crushed by a coarse rigid plate "
                   f"({len(plate)} shells), whole-model single-surface contact", endtim, endtim / 24, endcyc=ncycle)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 5), f10(t, t, t, t)]
    lines += ["*MAT_PIECEWISE_LINEAR_PLASTICITY", f10(1, 7850.0, 200e9, 0.3, 250e6, 1.0e9)]
    lines += ["*MAT_RIGID", f10(2, 7850.0, 200e9, 0.3)]
    lines += ["*PART", "tube", f10(1, 2, 1), "*PART", "plate", f10(2, 2, 2)]
    bottom = [k for k, x in sorted(nodes.items()) if x[2] == 0.0]
    lines += node_set(1, bottom) + ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 1, 1, 1)]
    lines += ["*DEFINE_CURVE", f10(7), f"{0.0:20.8e}{-10.0:20.8e}", f"{1.0:20.8e}{-10.0:20.8e}"]
    lines += ["*BOUNDARY_PRESCRIBED_MOTION_RIGID", f10(2, 3, 0, 7, 1.0)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    lines += ["*DATABASE_RCFORC", f10(endtim / 24)]
    lines += ["*NODE"] + [f"{k:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for k, (x, y, z) in sorted(nodes.items())]
    lines += ["*ELEMENT_SHELL"] + [f"{s[0]:8d}{1:8d}" + "".join(f"{n:8d}" for n in s[1:]) for s in shells]
    lines += [f"{s[0]:8d}{2:8d}" + "".join(f"{n:8d}" for n in s[1:]) for s in plate]
    write(path, lines)


def contact_decks(outdir):
    """The contact keyword variants and search policies on the cube and plate."""
    single = ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    contact_two_bars(outdir, n=40, slsfac=1.0)
    contact_two_bars(outdir, "two_bars_lagrange", xcontact=f10(0, 0, 0, 0, 0, 2), n=160)
    contact_block_on_block(outdir)
    contact_block_on_block(outdir, "block_on_block_lagrange", f10(0, 0, 0, 0, 0, 2))
    tube_crush(outdir)
    shell_fold(outdir)
    contact_block_impact(outdir, "blocks_impact_two_way", "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE")
    contact_block_impact(outdir, "blocks_impact_one_way", "CONTACT_AUTOMATIC_NODES_TO_SURFACE")
    contact_patch(outdir)
    shell_on_solid(outdir, "shell_edge_on_solid", True)
    shell_on_solid(outdir, "shell_lying_on_solid", False)
    shell_on_solid(outdir, "shell_edge_initially_penetrating", True, z0=5.0e-4)
    contact_friction(outdir, "friction_sliding", 1.0, 0.0)
    contact_friction(outdir, "friction_sticking", 0.0, 0.2 * 9.81)
    contact_block_plate(outdir, "search_adaptive", single, f10(2, 0, 0, 0, 0, 0, 0.0, 90))
    contact_block_plate(outdir, "search_default", single, f10(0, 0, 0, 0, 0, 0, 0.0, 90))
    contact_block_plate(outdir, "search_fixed_170", single, f10(1, 170, 0, 0, 0, 0, 0.0, 90))
    contact_block_plate(outdir, "variant_surface_to_surface",
                        ["*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_ID", f10(7) + "cube on plate", f10(1, 2, 3, 3), "", ""],
                        endtim=1.0e-4)
    contact_block_plate(outdir, "variant_nodes_to_surface",
                        ["*CONTACT_AUTOMATIC_NODES_TO_SURFACE", f10(91, 2, 4, 3), "", ""], endtim=1.0e-4)
    contact_block_plate(outdir, "variant_segment_and_shell_sets",
                        ["*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", f10(8, 9, 0, 1), "", ""], endtim=1.0e-4)
    contact_block_plate(outdir, "variant_general_part_set",
                        ["*CONTACT_AUTOMATIC_GENERAL", f10(5, 0, 2), "", ""], endtim=1.0e-4)
    contact_block_plate(outdir, "variant_single_all_but",
                        ["*CONTACT_SINGLE_SURFACE_ID", f10(3), f10(5, 0, 6), "", "", f10(0, 0.1, 0, 0, 0, 0, 5)],
                        endtim=1.0e-4)


def demo_cantilever(outdir):
    """A clamped steel cantilever of hexahedra set swinging by an initial
    velocity that grows along its length."""
    L, b, nx = 1.0, 0.1, 20
    nodes, hexes = block_mesh(nx, 2, 2, L, b, b)
    lines = common("demo: clamped elastic cantilever of hexahedra, swinging", 0.02, 1.0e-4)
    tip = [n for n, x in sorted(nodes.items()) if abs(x[0] - L) < 1e-12 and x[1] == 0.0 and x[2] == 0.0]
    lines += ["*DATABASE_NODOUT", f10(1.0e-4), "*DATABASE_HISTORY_NODE", f10(tip[0])]
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 210e9, 0.3)]
    lines += ["*HOURGLASS", f10(1, 4, 0.05)]
    lines += part(1, 1, "cantilever", hgid=1)
    lines += node_set(1, nodes_where(nodes, lambda x, y, z: x == 0.0))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 1, 1, 1)]
    lines += ["*INITIAL_VELOCITY_NODE"]
    for n, (x, y, z) in sorted(nodes.items()):
        if x > 0:
            lines.append(f"{n:10d}{0.0:10.4g}{0.0:10.4g}{2.0 * x / L:10.4g}")
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(os.path.join(outdir, "demo_cantilever.k"), lines)


def bench_block(nx, ny, nz, path, ncycle):
    """Benchmark: an nx x ny x nz block, clamped at one end, moving: every
    element deforms. Runs ncycle cycles."""
    nodes, hexes = block_mesh(nx, ny, nz, nx * 0.01, ny * 0.01, nz * 0.01)
    lines = common(f"benchmark block {nx}x{ny}x{nz} hexahedra", 1.0, 1.0, endcyc=ncycle)
    lines += ["*MAT_ELASTIC", f10(1, 7850.0, 210e9, 0.3)]
    lines += part(1, 1, "block")
    lines += node_set(1, nodes_where(nodes, lambda x, y, z: x == 0.0))
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 0, 0, 0)]
    lines += ["*INITIAL_VELOCITY", f10(0), f10(-5.0, 2.0, 1.0)]
    lines += node_cards(nodes) + solid_cards(hexes, 1)
    write(path, lines)


def bench_shells(nx, ny, path, ncycle, states_dt=None, contact=False):
    """Benchmark: an nx x ny plate of Belytschko-Tsay shells, *MAT_024 with 5
    points through the thickness, clamped on one edge and thrown out of its
    plane hard enough to yield. Runs ncycle cycles; states every states_dt
    if given; with contact, one whole-model single-surface contact (issue
    32's "250,000-shell plate with contact": every node a slave)."""
    a, b, t = nx * 0.01, ny * 0.01, 0.002
    lines = common(f"benchmark plate {nx}x{ny} Belytschko-Tsay shells, *MAT_024, NIP 5", 1.0, 1.0, endcyc=ncycle)
    lines += ["*SECTION_SHELL", f10(2, 2, 1.0, 5), f10(t, t, t, t)]
    lines += ["*MAT_PIECEWISE_LINEAR_PLASTICITY", f10(1, 7850.0, 210e9, 0.3, 250e6, 1e9)]
    lines += ["*PART", "plate", f10(1, 2, 1)]
    nid = lambda i, j: 1 + i + (nx + 1) * j
    lines += node_set(1, [nid(0, j) for j in range(ny + 1)])
    lines += ["*BOUNDARY_SPC_SET", f10(1, 0, 1, 1, 1, 1, 1, 1)]
    lines += ["*INITIAL_VELOCITY", f10(0), f10(0.0, 0.0, 30.0)]
    if states_dt:
        lines += ["*DATABASE_BINARY_D3PLOT", f"{states_dt:10.4e}"]
    if contact:
        lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    lines += ["*NODE"] + [f"{nid(i, j):8d}{a * i / nx:16.9e}{b * j / ny:16.9e}{0.0:16.9e}{0:8d}{0:8d}"
                          for j in range(ny + 1) for i in range(nx + 1)]
    lines += ["*ELEMENT_SHELL"] + [f"{1 + i + nx * j:8d}{1:8d}{nid(i, j):8d}{nid(i + 1, j):8d}{nid(i + 1, j + 1):8d}"
                                   f"{nid(i, j + 1):8d}" for j in range(ny) for i in range(nx)]
    write(path, lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--outdir", default="input_decks")
    ap.add_argument("--bench", nargs=4, metavar=("NX", "NY", "NZ", "FILE"))
    ap.add_argument("--cycles", type=int, default=200)
    ap.add_argument("--bench-shells", nargs=3, metavar=("NX", "NY", "FILE"))
    ap.add_argument("--bench-tubes", nargs=3, metavar=("NTX", "NTY", "FILE"))
    ap.add_argument("--bench-tube-plate", metavar="FILE")
    ap.add_argument("--endtim", type=float, default=0.012, help="--bench-tube-plate: end time")
    ap.add_argument("--states-dt", type=float, default=None, help="--bench-shells: states every DT")
    ap.add_argument("--contact", action="store_true", help="--bench-shells: a whole-model single-surface contact")
    args = ap.parse_args()
    if args.bench_tube_plate:
        bench_tube_plate(args.bench_tube_plate, args.endtim)
        return
    if args.bench_tubes:
        bench_tubes(int(args.bench_tubes[0]), int(args.bench_tubes[1]), args.bench_tubes[2], args.cycles)
        return
    if args.bench_shells:
        bench_shells(int(args.bench_shells[0]), int(args.bench_shells[1]), args.bench_shells[2], args.cycles,
                     args.states_dt, args.contact)
        return
    if args.bench:
        nx, ny, nz = (int(v) for v in args.bench[:3])
        bench_block(nx, ny, nz, args.bench[3], args.cycles)
        return
    bar_impact(args.outdir)
    free_block_spin(args.outdir)
    prestressed_block(args.outdir)
    bar_wall(args.outdir)
    bar_moving_wall(args.outdir, "bar_heavy_wall", 1000.0)
    bar_moving_wall(args.outdir, "bar_light_wall", 1.0)
    bar_on_pole(args.outdir)
    gravity_drop(args.outdir)
    tension_decks(args.outdir)
    taylor_bar(args.outdir, "taylor_bar_coarse", 3, 3, 36)
    taylor_bar(args.outdir, "taylor_bar_fine", 5, 5, 60)
    rigid_spin(args.outdir)
    rigid_block_wall(args.outdir, "rigid_block_wall", (0.0, 0.0))
    rigid_block_wall(args.outdir, "rigid_block_wall_corner", (30.0, 20.0))
    rod_with_rigid_mass(args.outdir)
    rigid_shell_spin(args.outdir)
    shell_warped_spin(args.outdir)
    rigid_prescribed(args.outdir)
    pressure_column(args.outdir)
    shell_cantilever(args.outdir)
    shell_tension(args.outdir)
    shell_tension_thick(args.outdir)
    shell_tension_tri(args.outdir)
    clamped_plate(args.outdir)
    mixed_deck(args.outdir)
    mixed_deck(args.outdir, gravity=True)
    spot_weld(args.outdir, "spot_weld", 1.0e20)
    spot_weld(args.outdir, "spot_weld_fail", 1.0e-6)
    demo_cantilever(args.outdir)
    contact_decks(args.outdir)
    import paper_decks
    paper_decks.all_decks(args.outdir)


if __name__ == "__main__":
    main()
