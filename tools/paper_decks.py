#!/usr/bin/python3
"""The three examples of section 7 of Whirley & Engelmann (1993) as decks.

    paper_decks.py [--outdir input_decks] [--refine R]

Writes input_decks/paper/{wide_flange_beam,wall_of_blocks,front_frame}.k.
gen_decks.py calls this too. --refine R divides every element size by R
(the shell decks) or multiplies the hexahedra per brick (the wall), for a
convergence check. Units are SI (m, kg, s, Pa).
"""
import argparse
import math
import os

from gen_decks import block_mesh, common, f10, node_cards, node_set, part, solid_cards, write


class ShellMesh:
    """Shells on a grid: nodes are merged by position (to 1e-7 m), so two
    plates that share an edge or meet at a T share its nodes."""

    def __init__(self):
        self.nodes, self.key, self.shells = {}, {}, []

    def node(self, x, y, z):
        k = (round(x * 1e7), round(y * 1e7), round(z * 1e7))
        if k not in self.key:
            n = len(self.nodes) + 1
            self.key[k] = n
            self.nodes[n] = (x, y, z)
        return self.key[k]

    def patch(self, pid, origin, u, v, nu, nv, warp=None):
        """A quadrilateral patch origin + s u + t v (s, t in [0, 1]) of nu x nv
        shells in part pid, numbered so that the normal is u x v. warp(x, y, z)
        may move a node. Returns the element ids."""
        ids = []
        grid = {}
        for j in range(nv + 1):
            for i in range(nu + 1):
                p = [origin[c] + u[c] * i / nu + v[c] * j / nv for c in range(3)]
                if warp:
                    p = warp(*p)
                grid[i, j] = self.node(*p)
        for j in range(nv):
            for i in range(nu):
                e = len(self.shells) + 1
                self.shells.append((e, pid, grid[i, j], grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]))
                ids.append(e)
        return ids

    def box(self, pid, lo, hi, n, open_faces=()):
        """The six faces of a box (outward normals) of n = (nx, ny, nz) shells
        a side; faces named '-x', '+x', ... in open_faces are left out."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        dx, dy, dz = x1 - x0, y1 - y0, z1 - z0
        nx, ny, nz = n
        faces = {"-z": ((x0, y0, z0), (0, dy, 0), (dx, 0, 0), ny, nx),
                 "+z": ((x0, y0, z1), (dx, 0, 0), (0, dy, 0), nx, ny),
                 "-y": ((x0, y0, z0), (dx, 0, 0), (0, 0, dz), nx, nz),
                 "+y": ((x0, y1, z0), (0, 0, dz), (dx, 0, 0), nz, nx),
                 "-x": ((x0, y0, z0), (0, 0, dz), (0, dy, 0), nz, ny),
                 "+x": ((x1, y0, z0), (0, dy, 0), (0, 0, dz), ny, nz)}
        ids = []
        for name, (o, u, v, nu, nv) in faces.items():
            if name not in open_faces:
                ids += self.patch(pid, o, u, v, nu, nv)
        return ids

    def cards(self):
        out = ["*NODE"] + [f"{k:8d}{x:16.9e}{y:16.9e}{z:16.9e}{0:8d}{0:8d}" for k, (x, y, z) in
                           sorted(self.nodes.items())]
        out += ["*ELEMENT_SHELL"] + ["".join(f"{v:8d}" for v in s) for s in self.shells]
        return out


def shell_section(secid, t, nip=5):
    """Shell section 10 + secid (section 1 is common()'s solid section)."""
    return ["*SECTION_SHELL", f10(10 + secid, 2, 1.0, nip), f10(t, t, t, t)]


def steel_024(mid, sigy=250e6, etan=1.0e9):
    """*MAT_024 mild steel: 7850 kg/m^3, 200 GPa, 0.3, bilinear hardening."""
    return ["*MAT_PIECEWISE_LINEAR_PLASTICITY", f10(mid, 7850.0, 200e9, 0.3, sigy, etan)]


def curve(lcid, pts):
    return ["*DEFINE_CURVE", f10(lcid)] + [f"{a:20.8e}{o:20.8e}" for a, o in pts]


def wide_flange_beam(outdir, refine=1, endtim=0.030):
    """Section 7.1: crush of a wide-flange beam by a pressure on its upper
    surface. A 0.3 m length of an I-beam 0.2 m deep with 0.2 m flanges
    (mid-surfaces), 4 mm flanges and a 1.5 mm web of *MAT_024 steel
    (250 MPa, 1 GPa tangent), 12.5 mm Belytschko-Tsay shells (1,152): the
    web meets both flanges at T-intersections with shared nodes. The lower
    flange is held vertically (its web line fully); the beam's ends are
    free. The web carries a 1 mm half-sine bow (a buckling seed). A
    pressure on the whole upper flange rises linearly to 0.5 MPa over half
    the run, then holds. The web buckles as a strip between the flanges at
    0.07 MPa pinned (p b = pi^2 E t^3 / (12 d^2)) to 0.28 MPa clamped; the
    flanges' plastic hinges at the web form at 0.2 MPa (p (b/2)^2 / 2 =
    sigma_y t^2 / 4): close together, as the paper's sequence needs (a
    thicker flange only tilts on the buckled web; a thinner one folds
    around the web, the follower pressure turns sideways and the web
    stands). Whole-model single-surface contact."""
    L, b, d, tf, tw = 0.3, 0.2, 0.2, 0.004, 0.0015
    h = 0.0125 / refine
    nl, nb, nd = round(L / h), round(b / h), round(d / h)
    m = ShellMesh()
    bow = 1.0e-3
    def web_warp(x, y, z):
        return (x, y + bow * math.sin(math.pi * z / d), z)
    # normals: upper flange +z (so that the pressure pushes down), lower -z
    upper = m.patch(1, (0.0, -b / 2, d), (L, 0, 0), (0, b, 0), nl, nb)
    web = m.patch(2, (0.0, 0.0, 0.0), (L, 0, 0), (0, 0, d), nl, nd, warp=web_warp)
    lower = m.patch(3, (0.0, -b / 2, 0.0), (0, b, 0), (L, 0, 0), nb, nl)
    lines = common(f"paper 7.1: crush of a wide-flange beam by a pressure on its upper surface "
                   f"({len(m.shells)} shells)", endtim, endtim / 150)
    lines += shell_section(1, tf) + shell_section(2, tw) + steel_024(1)
    lines += ["*PART", "upper flange", f10(1, 11, 1), "*PART", "web", f10(2, 12, 1),
              "*PART", "lower flange", f10(3, 11, 1)]
    low_nodes = sorted({n for s in m.shells if s[1] == 3 for n in s[2:]})
    web_line = [n for n in low_nodes if abs(m.nodes[n][1]) < 1e-9]
    lines += node_set(1, low_nodes) + ["*BOUNDARY_SPC_SET", f10(1, 0, 0, 0, 1, 0, 0, 0)]
    lines += node_set(2, web_line) + ["*BOUNDARY_SPC_SET", f10(2, 0, 1, 1, 1, 0, 0, 0)]
    lines += curve(1, [(0.0, 0.0), (0.5 * endtim, 5.0e5), (10.0 * endtim, 5.0e5)])
    lines += ["*SET_SEGMENT", f10(1)]
    lines += ["".join(f"{n:10d}" for n in m.shells[e - 1][2:]) for e in upper]
    lines += ["*LOAD_SEGMENT_SET", f10(1, 1, 1.0)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    lines += ["*DATABASE_RCFORC", f10(endtim / 150), "*DATABASE_BINARY_D3PLOT", f10(endtim / 60)]
    lines += m.cards()
    write(os.path.join(outdir, "paper", "wide_flange_beam.k"), lines)


def wall_of_blocks(outdir, nrow=4, ncol=6, gap=0.002, v0=10.0, endtim=0.04, refine=1, nb=2):
    """Section 7.2: a stiff elastic block striking the end of a wall of
    rigid blocks. The wall is nrow rows of ncol bricks (0.2 x 0.1 x 0.1 m,
    2 nb x nb x nb hexahedra each, 50 mm for nb = 2: a coarse mesh, as the
    paper keeps it; nb = 1, two hexahedra a brick, lets edges of rigid
    bricks sink 30-40 mm into the impactor's edges, edge to edge, where
    no node meets a face: the inaccuracy the paper notes), laid in
    running bond (alternate rows shifted by half a brick) with a gap between
    all bricks, so that nothing is in contact at the start and the run-time
    search finds every contact. Each brick is its own *MAT_RIGID part
    (concrete-like: 2400 kg/m^3, E 30 GPa for the contact stiffness). No
    gravity, no floor: the wall floats, as a test of the search rather than
    of masonry. The impactor, a steel block of 2 nb hexahedra a side (0.2 m),
    moves along the wall at v0 and strikes the lower two rows of the end
    column. Whole-model single-surface contact."""
    bl, bw, bh = 0.2, 0.1, 0.1
    nodes, elems = {}, []
    nid, eid = 1, 1
    lines = common("paper 7.2: a stiff elastic block strikes the end of a wall of rigid blocks", endtim, endtim / 200)
    lines += ["*MAT_RIGID", f10(1, 2400.0, 30e9, 0.2)]
    lines += ["*MAT_ELASTIC", f10(2, 7850.0, 200e9, 0.3)]
    pid = 0
    for r in range(nrow):
        shift = 0.5 * (bl + gap) if r % 2 else 0.0
        for c in range(ncol):
            pid += 1
            x0 = shift + c * (bl + gap)
            z0 = r * (bh + gap)
            bn, bx = block_mesh(2 * nb * refine, nb * refine, nb * refine, bl, bw, bh, origin=(x0, 0.0, z0), nid0=nid, eid0=eid)
            nodes.update(bn)
            lines += part(pid, 1, f"brick row {r + 1} column {c + 1}")
            elems.append((pid, bx))
            nid += len(bn)
            eid += len(bx)
    imp = pid + 1
    a = 0.2
    x0 = -gap - a - 0.003
    inodes, ihex = block_mesh(2 * nb * refine, 2 * nb * refine, 2 * nb * refine, a, a, a, origin=(x0, -0.05, 0.0), nid0=nid,
                              eid0=eid)
    nodes.update(inodes)
    # stiffness hourglass control (Flanagan-Belytschko, QM 0.05) on the
    # impactor: its strain energy returns to motion after the impact, and
    # viscous control on its coarse hexahedra, struck by the bricks' edges,
    # dissipated five times its largest internal energy
    lines += ["*HOURGLASS", f10(1, 4, 0.05)]
    lines += part(imp, 2, "impactor (elastic steel)", hgid=1)
    elems.append((imp, ihex))
    lines += node_set(1, sorted(inodes))
    lines += ["*INITIAL_VELOCITY", f10(1), f10(v0, 0.0, 0.0)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    lines += ["*DATABASE_RCFORC", f10(endtim / 200), "*DATABASE_BINARY_D3PLOT", f10(endtim / 80)]
    lines += node_cards(nodes)
    for p_, hx in elems:
        lines += solid_cards(hx, p_)
    write(os.path.join(outdir, "paper", "wall_of_blocks.k"), lines)


def front_frame(outdir, refine=1, v0=13.4, endtim=0.030):
    """Section 7.3: frontal impact of a vehicle front frame, half-symmetry
    (y >= 0, symmetry plane y = 0), x pointing forward, z up, on a 20 mm
    grid (nodes merged where members meet):
    - front crossmembers (parts 1 upper, 2 lower): steel channels 0.1 m deep
      with 60 mm flanges pointing forward to x = 0.80 (they strike the
      barrier first), webs in the plane x = 0.74, spanning y 0..0.5 m, at
      z 0.3..0.4 and 0..0.1;
    - middle crossmembers (3 upper, 4 lower): channels at x = 0.30 with the
      flanges pointing forward, and a plate (5) between them, in the webs'
      plane, z 0.1..0.3;
    - upper and lower energy absorbers (6, 7): 60 mm square tubes at
      y 0.40..0.46, from the middle to the front crossmember webs;
    - upper and lower rails (8, 9): the same tubes continued aft to x = 0.04,
      their last 40 mm (10) a rigid part carrying the rest of the half
      vehicle (about 150 kg), free only to move along x;
    - a rigid engine block (11): a 0.24 x 0.27 x 0.14 m box of rigid shells
      (about 80 kg, free only along x) 10 mm behind the plate, on its own
      40 mm mesh (its corners off the plate's grid lines, as in a real
      model: a corner aimed at a plate node sits in the tent of the four
      shells around it, where one contact segment a node cannot hold it);
    - a planar rigid wall at x = 0.81 (the barrier).
    Everything moves forward at v0 = 13.4 m/s (30 mph). Thicknesses: channels
    and plate 2 mm, tubes 1.5 mm; *MAT_024 steel 250 MPa, 1 GPa tangent.
    Whole-model single-surface contact."""
    g = 0.02 / refine
    def n(a):
        return max(1, round(a / g))
    m = ShellMesh()
    W = 0.50
    # front channels: web at x = 0.74 (normal +x), flanges forward to the
    # barrier at 0.80 (open side forward: the flanges strike first and fold)
    for pid, z0 in ((1, 0.30), (2, 0.0)):
        m.patch(pid, (0.74, 0.0, z0), (0, W, 0), (0, 0, 0.10), n(W), n(0.10))
        for z in (z0, z0 + 0.10):
            m.patch(pid, (0.74, 0.0, z), (0.06, 0, 0), (0, W, 0), n(0.06), n(W))
    # middle channels at x = 0.30, flanges forward to 0.36, plate between
    for pid, z0 in ((3, 0.30), (4, 0.0)):
        m.patch(pid, (0.30, 0.0, z0), (0, W, 0), (0, 0, 0.10), n(W), n(0.10))
        for z in (z0, z0 + 0.10):
            m.patch(pid, (0.30, 0.0, z), (0.06, 0, 0), (0, W, 0), n(0.06), n(W))
    m.patch(5, (0.30, 0.0, 0.10), (0, W, 0), (0, 0, 0.20), n(W), n(0.20))
    # square tubes y 0.40..0.46: absorbers 0.30..0.74, rails 0.08..0.30, rigid ends 0.04..0.08
    c = 0.06
    for (pa, pr), zc in (((6, 8), 0.35), ((7, 9), 0.05)):
        y0, z0 = 0.40, zc - c / 2
        for pid, xa, xb in ((pa, 0.30, 0.74), (pr, 0.08, 0.30), (10, 0.04, 0.08)):
            L = xb - xa
            m.patch(pid, (xa, y0, z0), (L, 0, 0), (0, c, 0), n(L), n(c))          # bottom, normal -z... any
            m.patch(pid, (xa, y0, z0 + c), (L, 0, 0), (0, c, 0), n(L), n(c))
            m.patch(pid, (xa, y0, z0), (L, 0, 0), (0, 0, c), n(L), n(c))
            m.patch(pid, (xa, y0 + c, z0), (L, 0, 0), (0, 0, c), n(L), n(c))
    # engine: rigid box behind the plate (open on the symmetry plane)
    ge = 0.04 / refine
    m.box(11, (0.05, 0.0, 0.13), (0.29, 0.27, 0.27), (round(0.24 / ge), round(0.27 / ge), round(0.14 / ge)),
          open_faces=("-y",))
    area = {}
    for s in m.shells:
        p = [m.nodes[k] for k in s[2:]]
        d1 = [p[2][i] - p[0][i] for i in range(3)]
        d2 = [p[3][i] - p[1][i] for i in range(3)]
        cr = (d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2], d1[0] * d2[1] - d1[1] * d2[0])
        area[s[1]] = area.get(s[1], 0.0) + 0.5 * math.sqrt(sum(v * v for v in cr))
    rho_rear = 150.0 / (area[10] * 0.0015)
    rho_engine = 80.0 / (area[11] * 0.002)
    lines = common(f"paper 7.3: frontal impact of a vehicle front frame, half model ({len(m.shells)} shells)",
                   endtim, endtim / 150)
    # the stiffness hourglass form (IHQ 4, QM 0.1; LS-DYNA's default is the
    # viscous IHQ 1): under the viscous form the channels' folds close
    # tighter, and two nodes at fold hinges pass through (refused as
    # contacts under flanks they did not cross; doc/theory.md)
    lines += ["*CONTROL_HOURGLASS", f10(4, 0.1)]
    lines += shell_section(1, 0.002) + shell_section(2, 0.0015) + shell_section(3, 0.0015, nip=2)
    lines += shell_section(4, 0.002, nip=2)
    lines += steel_024(1)
    lines += ["*MAT_RIGID", f10(2, rho_rear, 200e9, 0.3), f10(1.0, 5, 7)]
    lines += ["*MAT_RIGID", f10(3, rho_engine, 200e9, 0.3), f10(1.0, 5, 7)]
    names = {1: "front upper crossmember", 2: "front lower crossmember", 3: "middle upper crossmember",
             4: "middle lower crossmember", 5: "plate between the middle crossmembers",
             6: "upper energy absorber", 7: "lower energy absorber", 8: "upper rail", 9: "lower rail",
             10: "rail ends (rest of the vehicle, rigid)", 11: "engine block (rigid)"}
    secmat = {1: (1, 1), 2: (1, 1), 3: (1, 1), 4: (1, 1), 5: (1, 1), 6: (2, 1), 7: (2, 1), 8: (2, 1),
              9: (2, 1), 10: (3, 2), 11: (4, 3)}
    for pid in sorted(names):
        lines += ["*PART", names[pid], f10(pid, 10 + secmat[pid][0], secmat[pid][1])]
    allnodes = sorted(m.nodes)
    sym = [k for k in allnodes if abs(m.nodes[k][1]) < 1e-9
           and not any(s[1] == 11 and k in s[2:] for s in m.shells)]
    lines += node_set(1, allnodes) + ["*INITIAL_VELOCITY", f10(1), f10(v0, 0.0, 0.0)]
    # symmetry: y, and rotations about x and z
    lines += node_set(2, sym) + ["*BOUNDARY_SPC_SET", f10(2, 0, 0, 1, 0, 1, 0, 1)]
    lines += ["*RIGIDWALL_PLANAR", f10(0), f10(0.81, 0.0, 0.0, 0.80, 0.0, 0.0)]
    lines += ["*CONTACT_AUTOMATIC_SINGLE_SURFACE", f10(0), "", ""]
    lines += ["*DATABASE_RCFORC", f10(endtim / 150), "*DATABASE_RWFORC", f10(endtim / 150),
              "*DATABASE_BINARY_D3PLOT", f10(endtim / 60)]
    lines += m.cards()
    write(os.path.join(outdir, "paper", "front_frame.k"), lines)


def all_decks(outdir, refine=1):
    wide_flange_beam(outdir, refine=refine)
    wall_of_blocks(outdir, refine=refine)
    front_frame(outdir, refine=refine)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--outdir", default="input_decks")
    ap.add_argument("--refine", type=int, default=1)
    args = ap.parse_args()
    all_decks(args.outdir, args.refine)


if __name__ == "__main__":
    main()
