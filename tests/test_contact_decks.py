"""Contact decks with known answers: bars, blocks, the patch test, friction,
the tube crush, folds, edges, eroding contact and the torture suite.

Each check states its tolerance and why (tests/README.md: how to run
and add tests)."""
import pytest

from xdtest import *  # noqa: F401,F403 (the shared helpers and imports)


def sphere_solid_plate_deck(contact="ERODING_SURFACE_TO_SURFACE", top_only=False, v=400.0, tend=4e-5):
    """A rigid sphere (radius 4 mm, 96 shells of a cube projected on it,
    *MAT_RIGID of 78,500 kg/m3 as 1 mm shells: 16 g) at v onto a clamped
    solid steel plate (16 x 16 mm, 4 mm thick, 16 x 16 x 4 hexahedra,
    *MAT_024 300 MPa, tangent 1 GPa, FAIL 0.3); *CONTROL_CONTACT SLSFAC 1.
    The contact: the sphere's part against the plate's (surface to
    surface), or every part (single surface); top_only: the plate's side
    a *SET_SEGMENT of its top faces (no face inside it)."""
    R, n, nz, H, W, nsp = 0.004, 16, 4, 0.004, 0.016, 4
    L = ["*KEYWORD", "*TITLE", "a rigid sphere through an eroding solid plate", "*CONTROL_TERMINATION", f"{tend:10.3e}",
         "*CONTROL_CONTACT", "       1.0", "*DATABASE_GLSTAT", " 1.000e-06", "*DATABASE_MATSUM", " 1.000e-06",
         "*DATABASE_BINARY_D3PLOT", " 2.000e-06", "*SECTION_SOLID", "         1         1",
         "*SECTION_SHELL", "         2         2         1         2", "     0.001     0.001     0.001     0.001",
         "*MAT_PIECEWISE_LINEAR_PLASTICITY", "         1      7850     2e+11       0.3     3e+08     1e+09       0.3",
         "*MAT_RIGID", "         2     78500     2e+11       0.3",
         "*PART", "plate", "         1         1         1", "*PART", "sphere", "         2         2         2", "*NODE"]
    h, dz = W / n, H / nz
    nid, pl = 0, {}
    for k in range(nz + 1):
        for j in range(n + 1):
            for i in range(n + 1):
                nid += 1
                pl[i, j, k] = nid
                L.append(f"{nid:8d}{-W / 2 + i * h:16.9e}{-W / 2 + j * h:16.9e}{-H + k * dz:16.9e}       0       0")
    nid, quads = cube_sphere(L, nid, R, R + 0.0005, nsp)
    L.append("*ELEMENT_SOLID")
    e, top = 0, []
    for k in range(nz):
        for j in range(n):
            for i in range(n):
                e += 1
                c = [pl[i, j, k], pl[i + 1, j, k], pl[i + 1, j + 1, k], pl[i, j + 1, k],
                     pl[i, j, k + 1], pl[i + 1, j, k + 1], pl[i + 1, j + 1, k + 1], pl[i, j + 1, k + 1]]
                L.append(f"{e:8d}       1" + "".join(f"{x:8d}" for x in c))
                if k == nz - 1:
                    top.append(c[4:])
    L.append("*ELEMENT_SHELL")
    for c in quads:
        e += 1
        L.append(f"{e:8d}       2" + "".join(f"{x:8d}" for x in c))
    edge = [pl[i, j, k] for k in range(nz + 1) for j in range(n + 1) for i in range(n + 1) if i in (0, n) or j in (0, n)]
    L += ["*SET_NODE_LIST", "         1"] + [f"{x:10d}" for x in edge]
    L += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         1         1         1"]
    L += ["*INITIAL_VELOCITY_GENERATION", "         2         2       0.0       0.0       0.0" + f"{-v:10.4g}",
          "       0.0       0.0       0.0       0.0       0.0       0.0"]
    if top_only:
        L += ["*SET_SEGMENT", "         9"] + ["".join(f"{x:10d}" for x in q) for q in top]
        L += [f"*CONTACT_{contact}", "         2         9         3         0"]
    elif contact.endswith("SINGLE_SURFACE"):
        L += [f"*CONTACT_{contact}", "         0         0         5         0"]
    else:
        L += [f"*CONTACT_{contact}", "         2         1         3         3"]
    return "\n".join(L + ["*END"]) + "\n"


HEX_TETS = [(0, 1, 3, 4), (1, 2, 3, 6), (1, 4, 5, 6), (3, 4, 6, 7), (1, 3, 4, 6)]


def points_in_hexes(X, conn, pts, shrink):
    """How many of pts lie inside some hexahedron (conn over X) shrunk
    about its centroid by `shrink` (0.8: deeper than a tenth of the
    element below its faces), each split into five tetrahedra."""
    xe = X[conn]
    c = xe.mean(axis=1, keepdims=True)
    xe = c + shrink * (xe - c)
    lo, hi = xe.min(axis=1), xe.max(axis=1)
    n = 0
    for p in pts:
        hit = False
        for e in np.where(np.all((p >= lo) & (p <= hi), axis=1))[0]:
            for t in HEX_TETS:
                a = xe[e, t[0]]
                m = np.stack([xe[e, t[1]] - a, xe[e, t[2]] - a, xe[e, t[3]] - a], axis=1)
                if abs(np.linalg.det(m)) < 1e-30:
                    continue
                lam = np.linalg.solve(m, p - a)
                if lam.min() >= 0 and lam.sum() <= 1:
                    hit = True
                    break
            if hit:
                break
        n += hit
    return n


def test_solid_erosion_contact():
    """Contact that follows the erosion of solids (issue 33 deliverable 2):
    the faces inside a part that can erode are latent segments, exposed as
    their neighbours erode. A rigid sphere (16 g) at 400 m/s perforates a
    clamped 4 mm solid plate of four layers (*MAT_024 FAIL 0.3) through
    *CONTACT_ERODING_SURFACE_TO_SURFACE, and through
    *CONTACT_ERODING_SINGLE_SURFACE on every part. An independent
    geometric check on d3plot.h5's states (every 2 us, the living solids
    by solid_alive): no node of the sphere lies deeper than a tenth of an
    element inside a living solid (the solids shrunk by 0.8 about their
    centres); the same deck with the contact on the plate's top faces
    alone (a *SET_SEGMENT: no face inside) finds sphere nodes inside, so
    the check can fail. The solids erode (named in d3hsp, which counts the
    latent segments), the sphere leaves below the plate slower than it
    came, glstat books the eroded internal energy, and the energy ratio
    stays within 2% (the acceptance's) of 1. Two ranks and a restart
    mid-erosion give the serial histories bitwise."""
    def inside(out):
        with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
            conn = f["mesh/solid_connectivity"][:]
            sconn, spart = f["mesh/shell_connectivity"][:], f["mesh/shell_part"][:]
            sph = np.unique(sconn[spart == 2].ravel())
            counts = []
            for k in sorted(x for x in f["states"] if x != "time"):
                g = f["states/" + k]
                X, alive = g["coordinates"][:], g["solid_alive"][:] > 0.5
                counts.append(points_in_hexes(X, conn[alive], X[sph], 0.8))
        return counts
    for contact in ("ERODING_SURFACE_TO_SURFACE", "ERODING_SINGLE_SURFACE"):
        text = sphere_solid_plate_deck(contact)
        name = "solid_erosion_contact_" + contact.split("_")[1].lower()
        path = os.path.join(TMP, name + ".k")
        with open(path, "w") as f:
            f.write(text)
        out = os.path.join(TMP, name)
        p = run([XDYNA, "i=" + path, "outdir=" + out, "h5plot=1"])
        if p.returncode != 0:
            record(f"solid erosion contact ({contact}) runs", False, p.stderr[-300:])
            continue
        log = open(os.path.join(out, "d3hsp")).read()
        neroded = log.count("eroded at time")
        m = re.search(r"solids that can erode: (\d+) latent segments", log)
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            ratio, eroded = f["glstat/energy_ratio"][:], f["glstat/eroded_internal_energy"][-1]
            vz = f["matsum/z_momentum"][:, 1] / f["matsum/mass"][:, 1]
        with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
            last = sorted(x for x in f["states"] if x != "time")[-1]
            sconn, spart = f["mesh/shell_connectivity"][:], f["mesh/shell_part"][:]
            zmax = float(f[f"states/{last}/coordinates"][:][np.unique(sconn[spart == 2].ravel()), 2].max())
        counts = inside(out)
        dev = float(np.max(np.abs(ratio - 1)))
        record(f"solid erosion contact ({contact}): {neroded} solids eroded and named, {m.group(1) if m else 0} latent "
               f"segments in d3hsp; the sphere leaves below the plate (its top at {zmax * 1e3:.2f} mm, the plate's "
               f"bottom -4) at {-vz[-1]:.1f} m/s (from 400); no sphere node a tenth of an element inside a living "
               f"solid in {len(counts)} states (most in one: {max(counts)}); eroded internal energy {eroded:.1f} J in "
               f"glstat; energy ratio within 2% ({dev:.1e})",
               neroded > 50 and m is not None and zmax < -0.004 and 0 < -vz[-1] < 399 and max(counts) == 0
               and eroded > 0 and dev < 0.02)
        if contact == "ERODING_SURFACE_TO_SURFACE":
            if shutil.which("mpirun") is not None:
                record("solid erosion contact: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)",
                       *two_ranks_match(path, out))
            first = float(re.search(r"eroded at time\s+(\S+),", log).group(1))
            ok, msg = restart_matches("solid_erosion_contact_rs", text, 1.2e-5, 3e-5)
            record(f"solid erosion contact: a restart from 12 us (solids eroding since {first * 1e6:.2f} us) ends as "
                   f"the uninterrupted run (bitwise)", ok and first < 1.2e-5, msg)
    text = sphere_solid_plate_deck(top_only=True)
    path = os.path.join(TMP, "solid_erosion_contact_top.k")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(TMP, "solid_erosion_contact_top")
    p = run([XDYNA, "i=" + path, "outdir=" + out, "h5plot=1"])
    counts = inside(out) if p.returncode == 0 else []
    record(f"solid erosion contact: with the plate's top faces alone in the contact (no latent segment), the check "
           f"finds sphere nodes inside living solids (most in one state: {max(counts) if counts else '-'}): it can fail",
           p.returncode == 0 and max(counts) > 0, p.stderr[-300:])


@pytest.mark.slow(54)
def test_contact_suite():
    """The fast subset (about 40 cases) of the contact torture suite (`make
    contact-suite`, tools/contact_suite.py, issue 16): generated decks over
    the pair types, alignments, mesh ratios, speeds, thicknesses,
    enforcement and contact types, each held to its closed-form rebound or
    a bounce, no pass-through, the overlap bound, the energy band and max
    4u/delta <= 1. Among them the aligned two bars, 2x2 and 4x4 elements
    across, penalty and Lagrange: rebound within 2% of the 1-D answer and
    contact duration within 10% of 2L/c (the bars are 160 elements long: the
    lumped-mass bar's own rebound error, 2.4% at 80 elements with the
    Lagrangian projection, falls below 2% only there)."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import contact_suite as cs
    cs.OUT = os.path.join(TMP, "contact_suite")
    sel = cs.fast_subset(cs.cases())
    for c in sel:
        r = cs.run_case(c)
        if "fails_extra" in r:
            r["fails"].append(r.pop("fails_extra"))
        record(f"contact suite {r['name']}: {r['answer'] or 'runs'} (error {r['err']:+.4f})", not r["fails"],
               "; ".join(r["fails"]))


def bars_histories(out):
    """Time, the facing end nodes' x, the parts' x momentum and mass, and the
    energy ratio of a two-bars run."""
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        return (f["nodout/time"][:], f["nodout/x_coordinate"][:, 0], f["nodout/x_coordinate"][:, 1],
                f["matsum/x_momentum"][:], f["matsum/mass"][:], f["glstat/energy_ratio"][:])


def test_contact_bars():
    """Two equal elastic bars (nu = 0, 40 elements, 100 mm) meet head-on at
    +-5 m/s through whole-model single-surface penalty contact (SLSFAC 1).
    1-D theory: contact lasts 2L/c = 39.6 us and each bar leaves at -+5 m/s.
    Tolerances: momentum (zero in total) to 1e-10 of one bar's, an exact
    conservation law of equal and opposite pair forces; the contact time
    within 10% (the penalty spring adds compliance: 5.9% measured); the
    rebound within 2% (0.95% measured: what is missing rings on in the bars
    as the 40-element mesh's dispersion); energy ratio within 1e-4."""
    p, out = run_deck("input_decks/contact/two_bars_penalty.k", "contact_bars")
    if p.returncode != 0:
        record("contact two bars runs", False, p.stderr[-300:])
        return
    t, xa, xb, mom, mass, ratio = bars_histories(out)
    two_l_c = 2 * 0.1 / np.sqrt(200e9 / 7850.0)
    touching = t[xb - xa < 0]
    dur = (touching.max() - touching.min()) / two_l_c - 1 if touching.size else float("nan")
    record(f"contact bars: contact time within 10% of 2L/c ({dur:+.1%})", abs(dur) < 0.10)
    v = mom[-1] / mass[-1]
    record(f"contact bars: bars leave with reversed velocities within 2% ({v[0]:.3f}, {v[1]:.3f} m/s)",
           abs(v[0] + 5) < 0.1 and abs(v[1] - 5) < 0.1)
    drift = np.max(abs(mom.sum(axis=1))) / (mass[0, 0] * 5)
    record(f"contact bars: momentum conserved to {roundoff(1e-10):.0e} ({drift:.1e})", drift < roundoff(1e-10))
    dev = np.max(abs(ratio - 1))
    record(f"contact bars: energy ratio within 1e-4 ({dev:.1e})", dev < 1e-4)


@pytest.mark.slow(40)
def test_contact_bars_lagrange():
    """The two bars with the Lagrangian projection (ENFORCE 2, no penalty
    stiffness), 160 elements each: once in contact the faces stop
    approaching, so the contact time is the bars' own. Tolerances: contact
    time within 2% of 2L/c (issue 5's figure); penetration under 1 um (the
    approach of one step before the pair is found); momentum to 1e-10;
    energy ratio within 1e-4 (the projection's loss, the end nodes' kinetic
    energy at first touch, is booked as sliding energy); rebound velocities
    within 2%. The rebound converges with the mesh: 3.2%, 2.3% and 1.6%
    short with 40, 80 and 160 elements (the sudden stop of the end nodes
    rings on in the bars as the mesh's dispersion; penalty: 0.95%, 0.68%,
    0.53%), so this test uses 160."""
    p, out = run_deck("input_decks/contact/two_bars_lagrange.k", "contact_bars_lagrange")
    if p.returncode != 0:
        record("contact two bars (Lagrange) runs", False, p.stderr[-300:])
        return
    t, xa, xb, mom, mass, ratio = bars_histories(out)
    two_l_c = 2 * 0.1 / np.sqrt(200e9 / 7850.0)
    gap = xb - xa
    touching = t[gap <= 1e-12]
    dur = (touching.max() - touching.min()) / two_l_c - 1 if touching.size else float("nan")
    record(f"contact bars, Lagrange: contact time within 2% of 2L/c ({dur:+.1%}), penetration under 1 um "
           f"({-gap.min() * 1e6:.2f} um)", abs(dur) < 0.02 and -gap.min() < 1e-6)
    drift = np.max(abs(mom.sum(axis=1))) / (mass[0, 0] * 5)
    dev = np.max(abs(ratio - 1))
    record(f"contact bars, Lagrange: momentum to {roundoff(1e-10):.0e} ({drift:.1e}), energy ratio within 1e-4 ({dev:.1e})",
           drift < roundoff(1e-10) and dev < 1e-4)
    va, vb = mom[-1, 0] / mass[0, 0], mom[-1, 1] / mass[0, 1]
    record(f"contact bars, Lagrange: bars leave with reversed velocities within 2% ({va:+.3f}, {vb:+.3f} m/s)",
           abs(va + 5) < 0.1 and abs(vb - 5) < 0.1)


def test_shell_fold():
    """A U-shaped 1 mm steel strip, its upper leg pushed down by pressure
    onto its clamped lower leg (one part: shell self-contact, two-sided
    segments with half-thickness offsets). The upper leg must come down
    (a node within 1.2 mm of the lower leg's mid-surface: in contact) and
    never closer than 90% of the thickness sum (0.9 mm, issue 5's bound);
    the independent checker finds no pass-through."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import penetration
    deck = "input_decks/contact/shell_fold.k"
    p, out = run_deck(deck, "shell_fold")
    if p.returncode != 0:
        record("shell fold runs", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        z = f["nodout/z_coordinate"][:]
    upper = np.nonzero(abs(z[0] - 0.01) < 1e-9)[0]
    zmin = z[:, upper].min()
    record(f"shell fold: the upper leg lands on the lower one (closest mid-surface gap {zmin * 1e3:.3f} mm, "
           f"within 0.9-1.2 mm: 90% of the 1 mm thickness sum or more)", 0.9e-3 <= zmin < 1.2e-3)
    worst, crossings = penetration.check(os.path.join(ROOT, deck), os.path.join(out, "thist.h5"))
    record(f"shell fold: no pass-through ({crossings}), overlap {worst:.1%} of the thickness (under 10%)",
           crossings == 0 and worst < 0.1)


def test_shell_on_solid():
    """Shell-solid contact (nodes-to-surface, the plate's nodes on the
    block's faces). Edge on: a 2 mm plate falling on its edge at 2 m/s hits
    the block's face with its half-thickness (1 mm): its edge must stay on
    the right side, above 1 mm less 10% of the half-thickness; it must
    bounce (upward velocity at the end); the contact impulse (rcforc,
    every 1 us) must equal the plate's change of momentum within 2%
    (action and reaction; the sampling of a 10 us pulse limits it). Lying
    flat under gravity on the face: the mid-surface stays at t/2 = 1 mm
    (within 1 um) and rcforc carries the plate's weight within 0.5% over
    the second half of the run (it rings a little after the start)."""
    p, out = run_deck("input_decks/contact/shell_edge_on_solid.k", "shell_edge_on")
    if p.returncode == 0:
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            z = f["nodout/z_coordinate"][:]
            t, fz = f["rcforc/time"][:], f["rcforc/slave_z_force"][:, 0]
            mass = f["matsum/mass"][0, 1]
            vz = f["matsum/z_momentum"][:, 1] / mass
        imp = np.trapz(fz, t)
        dp = mass * (vz[-1] - vz[0])
        record(f"shell edge on a solid face: edge stays above 0.9 mm ({z.min() * 1e3:.3f} mm) and the plate "
               f"bounces ({vz[-1]:+.2f} m/s)", z.min() > 0.9e-3 and vz[-1] > 0.5)
        record(f"shell edge on a solid face: contact impulse {imp:.4f} N s = plate's momentum change "
               f"{dp:.4f} within 2%", abs(imp / dp - 1) < 0.02)
    else:
        record("shell edge on solid runs", False, p.stderr[-300:])
    p, out = run_deck("input_decks/contact/shell_lying_on_solid.k", "shell_lying")
    if p.returncode == 0:
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            z = f["nodout/z_coordinate"][:]
            fz = f["rcforc/slave_z_force"][:, 0]
            mass = f["matsum/mass"][0, 1]
        w = mass * 9.81
        carried = fz[len(fz) // 2:].mean() / w - 1
        record(f"shell lying on a solid face: mid-surface stays at 1 mm ({abs(z - 1e-3).max() * 1e6:.3f} um "
               f"off) and the contact carries its weight ({carried:+.2%}, within 0.5%)",
               abs(z - 1e-3).max() < 1e-6 and abs(carried) < 0.005)
    else:
        record("shell lying on solid runs", False, p.stderr[-300:])


def test_edge_contact():
    """Edge-to-edge contact (*CONTACT_AUTOMATIC_GENERAL): two 1 mm plates in
    perpendicular planes thrown at each other at 10 m/s, their leading
    edges crossing half an element from any node (no node comes near the
    other plate). With AUTOMATIC_GENERAL the edges meet and part on their
    own sides (the edges' overlap under half the thickness: the suite's
    band), the contact's work negative (frictionless springs return what
    they took: the sliding energy ends within 1e-3 of the initial kinetic
    energy and never below -0.1% of it), d3hsp counts the exterior edges and
    the pair-cycles in contact and names no allowance (none is needed at
    10 m/s); with AUTOMATIC_SINGLE_SURFACE (no edge contact, as LS-DYNA's)
    the same plates pass through each other, which shows the check sees a
    pass. On 2 MPI ranks the general run's histories are the serial ones
    bitwise (every rank computes every edge pair alike)."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import contact_suite as cs
    cs.OUT = os.path.join(TMP, "edge_contact")
    want = {"crossed_edges_general_pen_half_1to1_k2_v10_t1mm", "crossed_edges_single_pen_half_1to1_k2_v10_t1mm"}
    res = {}
    for c in cs.cases():
        if c["name"] in want:
            r = cs.run_case(c)
            d = os.path.join(cs.OUT, c["name"])
            log = open(os.path.join(d, "d3hsp")).read() if os.path.exists(os.path.join(d, "d3hsp")) else ""
            res[c["type"]] = (r, d, log)
    if set(res) != {"general", "single"}:
        record("edge contact: both crossed-edges cases generated", False)
        return
    r, d, log = res["general"]
    with h5py.File(os.path.join(d, "thist.h5"), "r") as f:
        slide = f["glstat/sliding_interface_energy"][:]
        ke0 = f["glstat/kinetic_energy"][0]
    m = re.search(r"edge to edge: (\d+) exterior shell edges, (\d+) edge pair-cycles in contact", log)
    ncont = int(m.group(2)) if m else 0
    record(f"edge contact: AUTOMATIC_GENERAL holds edges crossing away from the nodes (edge overlap "
           f"{r.get('edge_overlap', float('nan')):.3f} of the thickness, band 0.5; {ncont} pair-cycles in contact)",
           r["rc"] == 0 and "fails_extra" not in r and not r["fails"] and ncont > 0,
           "; ".join(r["fails"] + [r.get("fails_extra", "")]))
    record(f"edge contact: the frictionless edge springs do no net positive work (sliding energy min "
           f"{slide.min() / ke0:+.2e}, end {slide[-1] / ke0:+.2e} of KE0; bands -1e-3, |end| 1e-3)",
           slide.min() >= -1e-3 * ke0 and abs(slide[-1]) <= 1e-3 * ke0)
    record("edge contact: d3hsp names the exterior edges (24) and no edge allowance at 10 m/s",
           m is not None and int(m.group(1)) == 24 and "edge contact found deeper" not in log
           and "no side known" not in log)
    r, d, log = res["single"]
    record("edge contact: a single surface (no edge contact) lets the same edges pass (the check sees a pass)",
           r["rc"] == 0 and "passed each other" in r.get("fails_extra", ""), r.get("fails_extra", ""))
    if shutil.which("mpirun") is None:
        return
    serial = res["general"][1]
    out = os.path.join(TMP, "edge_contact_mpi2")
    p = mpirun(2, ["i=" + os.path.join(serial, "deck.k"), "outdir=" + out])
    ok, msg = (False, p.stderr[-300:]) if p.returncode else ranks_match(serial, out)
    record("edge contact: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)", ok, msg)


def test_blocks_impact():
    """A block striking a block with non-matching meshes at 1 m/s, penalty
    contact both ways (surface-to-surface) and one way (nodes-to-surface):
    equal and opposite pair forces conserve momentum (to 1e-12), and a
    conservative penalty conserves energy (to 1e-5; 2e-7 and 1e-9
    measured). Before solid tube contacts were limited to slaves well behind
    the face, the one-way run blew up: the upper block's edge nodes, in the
    plane of the lower block's side faces, were taken 8 mm deep into them."""
    for name in ("blocks_impact_two_way", "blocks_impact_one_way"):
        p, out = run_deck(f"input_decks/contact/{name}.k", name)
        if p.returncode != 0:
            record(f"contact {name} runs", False, p.stderr[-300:])
            continue
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            ratio = f["glstat/energy_ratio"][:]
            pzp = f["matsum/z_momentum"][:]
            pz = pzp.sum(axis=1)
            hit = abs(pzp[-1, 0]) / abs(pzp[0, 1])
        dev = np.max(abs(ratio - 1))
        drift = np.max(abs(pz - pz[0])) / abs(pz[0])
        record(f"contact {name}: energy within 1e-5 ({dev:.1e}), momentum within 1e-12 ({drift:.1e}), "
               f"the struck block takes {hit:.0%} of the momentum (over 50%)",
               dev < 1e-5 and drift < 1e-12 and hit > 0.5)


def test_contact_block_on_block():
    """A 0.1 m steel cube on a fixed block under gravity, solid on solid,
    penalty contact: the cube's lower nodes must not sink into the block by
    more than 1% of the solid thickness (the depth window, here V/A = 33 mm
    of the cube's and 25 mm of the block's elements: 0.25 mm), and the cube
    must be held (it does not fall through)."""
    p, out = run_deck("input_decks/contact/block_on_block.k", "contact_block_on_block")
    if p.returncode != 0:
        record("contact block on block runs", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        z = f["nodout/z_coordinate"][:]
    pen = -np.min(z)
    record(f"contact block on block: penetration {pen * 1e6:.3f} um under 1% of the thickness (250 um)",
           pen < 2.5e-4)
    record("contact block on block: the cube is held (its lower face stays within 1 mm of z = 0)",
           np.max(abs(z[-1])) < 1e-3)
    # a resting contact: the motion never uses the pool margin, so the
    # default searches once, at cycle 0 (before 2026-11-26 it also searched
    # every 100 cycles: 68 searches here, each finding the same lists)
    log = open(os.path.join(out, "d3hsp")).read()
    ns, worst = interface_line(log, 2), interface_line(log, 8)
    record(f"contact block on block: searched {ns:.0f} time(s) over the run (1: the motion, 4u/delta "
           f"{worst:.3f}, never calls for another)", ns == 1 and worst <= 1.0)
    # Lagrangian projection: the constraint stops every approach, so the
    # cube stays where it was put; 1e-6 of the 25 mm window (25 nm) bounds
    # what is left (5 nm measured: the first step's fall, and the
    # non-matching meshes' interpolation)
    p, out = run_deck("input_decks/contact/block_on_block_lagrange.k", "contact_block_on_block_lagrange")
    if p.returncode != 0:
        record("contact block on block (Lagrange) runs", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        z = f["nodout/z_coordinate"][:]
    pen = -np.min(z)
    # (1e-6 of the 25 mm thickness: round-off; 1e-5 of it in 32 bits)
    record(f"contact block on block, Lagrange: penetration {pen * 1e9:.2f} nm under {roundoff(2.5e-8, 0.025) * 1e9:.0f} nm",
           pen < roundoff(2.5e-8, 0.025))


def test_contact_patch():
    """Contact patch test: 10 MPa ramped over 1 ms on the top of a 3x3x2
    block stacked on a 4x4x2 block (non-matching meshes, nu = 0, edges
    aligned), the lower block held at its base, surface-to-surface penalty
    contact (two-way). With the load held (1.1-1.5 ms, time-averaged: the
    stack rings at 3% about its static state), the answer is p times each
    node's tributary area:
    - base reactions (the nodal reactions) within 5% (4.4% measured);
    - the sum of the contact forces and of the reactions within 0.5% of
      p A (equilibrium);
    - contact forces on the upper block's interface nodes within 5% (2.8%),
      and on the lower block's, except its four corners, within 5% (4.3%).
    The lower corners carry +15%: each coincides with an upper corner, so
    both passes put the whole corner spring of the other block on it; a
    node-to-segment reaction spread with the shape functions at the contact
    point (which keeps angular momentum) cannot do otherwise there. They
    are held within 20% so that a regression shows."""
    p, out = run_deck("input_decks/contact/patch_test.k", "contact_patch")
    if p.returncode != 0:
        record("contact patch test runs", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        t = f["nodout/time"][:]
        fz = f["nodout/z_contact_force"][:]
        rz = f["nodout/z_reaction_force"][:]
    hold = t > 1.1e-3
    pa = 1.0e7
    wl = np.outer([.5, 1, 1, 1, .5], [.5, 1, 1, 1, .5]).ravel() * 0.025 ** 2 * pa
    wu = np.outer([.5, 1, 1, .5], [.5, 1, 1, .5]).ravel() * (0.1 / 3) ** 2 * pa
    lower = -fz[hold][:, :25].mean(0) / wl
    upper = fz[hold][:, 25:41].mean(0) / wu
    base = rz[hold][:, 41:].mean(0) / wl
    err = abs(base - 1).max()
    record(f"contact patch test: base reactions within 5% of p times the tributary area ({err:.1%})", err < 0.05)
    tot = max(abs(-fz[hold][:, :25].sum(1).mean() / (pa * 0.01) - 1), abs(rz[hold][:, 41:].sum(1).mean() / (pa * 0.01) - 1))
    record(f"contact patch test: contact and base forces sum to p A within 0.5% ({tot:.2%})", tot < 0.005)
    corner = np.zeros(25, dtype=bool)
    corner[[0, 4, 20, 24]] = True
    eu, el, ec = abs(upper - 1).max(), abs(lower[~corner] - 1).max(), abs(lower[corner] - 1).max()
    record(f"contact patch test: interface nodal forces within 5% (upper {eu:.1%}, lower {el:.1%}); "
           f"coinciding corners within 20% ({ec:.1%})", eu < 0.05 and el < 0.05 and ec < 0.2)


def test_contact_swept_onset():
    """A penalty spring's onset and release swept over the step (issue 28):
    a 0.1 mm elastic plate falls flat at 10 m/s onto a free rigid block of
    its mass (the contact suite's shell_on_block case, SLSFAC 0.1 x 4, the
    contact's step bound setting the step), from nine heights spread over
    one step's approach, the first inside it (found ahead of touching at
    cycle 0: the half step's path). Every node meets the block at the same
    phase of the step, so nothing averages out. Taken at x(n) alone, the
    spring starts and stops at whatever point of the step the surface is
    crossed: these nine bounces gained up to 1.5% of their energy and lost
    up to 1.5%. Swept over the node's path, a one-mass bounce gains at most
    5e-4 and loses at most 0.3% at omega dt 0.5 (1.4e-3 and 0.57% at 0.55;
    two equal masses on the spring sit near there at the step bound).
    Bands: the sliding energy never below -1e-3 of the initial kinetic
    energy at any output (the issue's bound: a frictionless contact does no
    net positive work), and the kinetic energy after the bounce within 0.75%
    of the initial (the one-mass loss at 0.55 with room for the plate's
    vibration). Measured when written: worst gain 2.5e-4, worst change
    0.44%."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import contact_suite as cs
    g = cs.g
    worst_gain, worst_loss, rows = 0.0, 0.0, []
    ok = True
    for j in range(9):
        gap = 2.0e-7 + j * 4.0e-7
        c = {"name": f"swept_{j}", "family": "shell_on_block", "type": "single", "lag": False, "ratio": "1:1",
             "align": "node", "k": 4, "v": 10.0, "t": 1.0e-4, "seed": 0, "gap": gap}
        lines, _ = cs.shell_on_block(c)
        out = os.path.join(TMP, "swept_onset", c["name"])
        os.makedirs(out, exist_ok=True)
        g.write(os.path.join(out, "deck.k"), lines)
        p = run([XDYNA, "i=deck.k"], cwd=out)
        if p.returncode != 0:
            ok = False
            rows.append(f"gap {gap:.1e}: exit {p.returncode}")
            continue
        e = glstat(out)
        ke0 = e["kinetic_energy"][0]
        gain = max(0.0, -e["sliding_interface_energy"].min()) / ke0
        loss = 1.0 - e["kinetic_energy"][-1] / ke0
        at_bound = "the contact sets the time step" in open(os.path.join(out, "d3hsp")).read()
        worst_gain, worst_loss = max(worst_gain, gain), max(worst_loss, abs(loss))
        ok = ok and gain <= 1e-3 and abs(loss) <= 7.5e-3 and at_bound
        rows.append(f"gap {gap:.1e}: gain {gain:.1e}, KE loss {loss:+.2e}, step bound {at_bound}")
    record(f"contact: a thin plate's flat bounce at nine phases of the step keeps its energy (worst gain "
           f"{worst_gain:.1e} <= 1e-3, worst kinetic energy change {worst_loss:.1e} <= 7.5e-3)", ok, "; ".join(rows))


def test_contact_friction():
    """Coulomb friction FS = FD = 0.3 between a soft cube and a fixed block
    under gravity (surface-to-surface). Sliding at 1 m/s: the cube
    decelerates at mu g = 2.943 m/s^2 (fit of its mean velocity from 10 ms
    on; tolerance 2%, the normal force rings a little after the start).
    Under a side load of 0.2 g, below the static limit 0.3 g, the cube
    sticks: its mean velocity stays under 1% of the 0.098 m/s it would
    reach in 50 ms without friction. The same with the Lagrangian
    projection (ENFORCE 2), same bands: friction from the projected normal
    impulse (it had none: the penalty's cap mu k a is 0 there)."""
    for method in ("", "Lagrangian"):
        for name in ("friction_sliding", "friction_sticking"):
            deck = os.path.join(ROOT, "input_decks", "contact", name + ".k")
            if method:
                deck2 = os.path.join(TMP, f"contact_{name}_lagrange.k")
                with open(deck) as fh, open(deck2, "w") as out_fh:
                    out_fh.write(fh.read().replace("*END", "*CONTROL_XDYNA_CONTACT\n" +
                                                   "%10d" * 6 % (0, 0, 0, 0, 0, 2) + "\n*END"))
                deck = deck2
            tag = "contact friction" + (", " + method if method else "")
            p, out = run_deck(deck, "contact_" + name + ("_lagrange" if method else ""))
            if p.returncode != 0:
                record(f"{tag}: {name} runs", False, p.stderr[-300:])
                continue
            with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
                t, px, mass = f["matsum/time"][:], f["matsum/x_momentum"][:, 1], f["matsum/mass"][0, 1]
                ratio = f["glstat/energy_ratio"][:]
            v = px / mass
            if name == "friction_sliding":
                k = t > 0.01
                err = -np.polyfit(t[k], v[k], 1)[0] / (0.3 * 9.81) - 1
                record(f"{tag}: sliding cube decelerates at mu g within 2% ({err:+.2%})", abs(err) < 0.02)
                if not method:
                    dev = np.max(abs(ratio - 1))
                    record(f"{tag}: energy balance with friction's dissipation in the sliding energy "
                           f"within 1e-3 ({dev:.1e})", dev < 1e-3)
            else:
                record(f"{tag}: below the static limit the cube sticks (|v| {abs(v[-1]):.1e} m/s "
                       f"< 1e-3)", abs(v[-1]) < 1e-3)


def test_tube_crush():
    """Square steel tube (50 mm, 1.5 mm wall, 1200 Belytschko-Tsay shells,
    *MAT_024) crushed at 10 m/s with whole-model single-surface contact,
    the deck's 6 ms (60 mm of crush; make check ran 4 ms before the deck's
    hourglass QM went from 0.1 to 0.02, which lets the folds form later:
    2 lobes over 3 mm at 4 ms, 3 at 6 ms).
    Checks: energy ratio within 5% (the prescribed motion's work is
    external work); hourglass energy under 10% of the internal energy (the
    analysts' flag; it was 20% at QM 0.1); progressive folding: the middle
    line of one face shows at least three lobes of 3 mm or more,
    alternating in and out; no node
    passes through a shell, and no overlap deeper than 20% of the
    thickness between nodes and segments free of the 40 top nodes under
    prescribed motion, by tools/penetration.py (which finds 8
    pass-throughs and 90% overlap in the same run without contact). The
    top nodes' own pairs are reported, not held to the 20%: a node whose
    motion is prescribed goes where the curve drives it whatever force
    the contact puts on it, and a segment it drives does the same to a
    node caught under it (at 10 m/s into a fold backed by the folds
    below, the penalty force reaches the contact's thickness: with the
    bounded hourglass, issue 28, a top corner node ended 0.91 of the
    thickness deep while every other pair stayed within 0.13; with a
    shell contact held where it is found, 0.30 and 0.055). The mean crush force is
    set against Abramowicz & Jones, P = 13.06 sigma0 t^(5/3) C^(1/3) =
    23.6 kN (sigma0 = 250 MPa): reported, with a wide band (0.5x to 2.5x)
    because the 5 mm mesh puts three elements in a half fold (A&J's H =
    15 mm), the material hardens (1 GPa tangent) and the crush is dynamic."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import penetration
    deck = "input_decks/contact/tube_crush.k"
    endtim = 6.0e-3
    p, out = run_deck(deck, "tube_crush", extra=(f"endtim={endtim}",))
    if p.returncode != 0:
        record("tube crush runs", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        ratio, t, w = f["glstat/energy_ratio"][:], f["glstat/time"][:], f["glstat/external_work"][:]
        x, y, z = f["nodout/x_coordinate"][:], f["nodout/y_coordinate"][:], f["nodout/z_coordinate"][:]
    dev = np.max(abs(ratio - 1))
    record(f"tube crush: energy ratio within 5% ({dev:.1e})", dev < 0.05)
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        share = f["glstat/hourglass_energy"][-1] / f["glstat/internal_energy"][-1]
    record(f"tube crush: hourglass energy under 10% of the internal energy ({share:.1%})", share < 0.10)
    line = np.nonzero((abs(x[0] - 0.025) < 1e-9) & (abs(y[0]) < 1e-9))[0]
    u = (x[-1, line] - 0.025)[np.argsort(z[0, line])]
    ext = [i for i in range(1, len(u) - 1) if abs(u[i]) > 3e-3 and
           ((u[i] > u[i - 1] and u[i] >= u[i + 1]) or (u[i] < u[i - 1] and u[i] <= u[i + 1]))]
    alternating = all(np.sign(u[a]) != np.sign(u[b]) for a, b in zip(ext, ext[1:]))
    record(f"tube crush: progressive folds, {len(ext)} lobes over 3 mm alternating out and in (at least 3)",
           len(ext) >= 3 and alternating)
    worst, crossings = penetration.check(os.path.join(ROOT, deck), os.path.join(out, "thist.h5"))
    driven = penetration.prescribed_nodes(os.path.join(ROOT, deck))
    free, free_crossings = penetration.check(os.path.join(ROOT, deck), os.path.join(out, "thist.h5"), driven)
    record(f"tube crush: no node passes through a shell ({crossings}), and overlap under 20% of the thickness "
           f"between the nodes and segments free of the {len(driven)} top nodes under prescribed motion "
           f"({free:.1%}; with theirs {worst:.1%}, not held: see the test), by the independent penetration checker",
           crossings == 0 and len(driven) == 40 and free < 0.2)
    crush = 10.0 * t[-1]
    pm = (w[-1] - np.interp(5e-4, t, w)) / (crush - 0.005)
    paj = 13.06 * 250e6 * 1.5e-3 ** (5 / 3) * 0.05 ** (1 / 3)
    record(f"tube crush: mean crush force {pm / 1e3:.1f} kN against Abramowicz & Jones "
           f"{paj / 1e3:.1f} kN ({pm / paj - 1:+.0%}; band 0.5x-2.5x, see the test)", 0.5 < pm / paj < 2.5)


@pytest.mark.slow(25)
def test_wall_of_blocks():
    """Paper 7.2 (input_decks/paper/wall_of_blocks.k): a 0.2 m steel block at
    10 m/s strikes the end of a floating wall of 24 rigid bricks, all apart
    at the start, whole-model single-surface contact, 40 ms.
    - No external force: the total momentum (matsum, all parts) stays
      within 1e-6 of the impactor's initial 628 kg m/s (penalty forces act
      in equal and opposite pairs);
    - energy ratio within 1% throughout (no dissipation but the contact's
      and the hourglass's, both booked);
    - the motion spreads from the struck end: the struck bricks (row 1 and 2
      of column 1) move before any brick of the far column 6;
    - the penetration checker finds no node deeper than 20% of the local
      thickness and no pass-through (issue 7);
    - the frictionless contact does no net positive work: the sliding
      energy never below -0.1% of the initial kinetic energy (springs store
      and give back; round-off and the step's onset and release stay far
      inside that), and the kinetic energy at the end no more than the
      initial (nothing but the impactor's motion feeds the wall).
    The run is chaotic (a many-body impact: the smallest change of the
    arithmetic, another CPU or compiler, shifts a contact by a cycle and the
    bricks' paths apart), so it is held to these physical facts, not to a
    stored history (a 1e-4 comparison failed on another processor)."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import penetration
    p, out = run_deck("input_decks/paper/wall_of_blocks.k", "wall_of_blocks")
    record("wall of blocks runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        m = f["matsum"]
        t = m["time"][:]
        ids = m["ids"][:]
        mom = np.stack([m["x_momentum"][:].sum(1), m["y_momentum"][:].sum(1), m["z_momentum"][:].sum(1)], -1)
        ke = m["kinetic_energy"][:]
    dev = np.max(np.linalg.norm(mom - mom[0], axis=1)) / np.linalg.norm(mom[0])
    record(f"wall of blocks: total momentum conserved within 1e-6 ({dev:.1e} of {np.linalg.norm(mom[0]):.1f} kg m/s)",
           dev < 1e-6)
    g = glstat(out)
    edev = np.max(abs(g["energy_ratio"] - 1))
    record(f"wall of blocks: energy ratio within 1% throughout ({edev:.1e})", edev < 0.01)
    def first_move(pids):
        cols = [list(ids).index(q) for q in pids]
        moving = np.nonzero(ke[:, cols].max(1) > 1e-3)[0]
        return t[moving[0]] if len(moving) else np.inf
    t_struck, t_far = first_move([1, 7]), first_move([6, 12, 18, 24])
    record(f"wall of blocks: the struck bricks move first ({t_struck * 1e3:.2f} ms), the far column later "
           f"({t_far * 1e3:.2f} ms)", t_struck < t_far < np.inf)
    with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
        parts = set(f["mesh/solid_part"][:].tolist())
        nsol = len(f["mesh/solid_part"])
    record(f"wall of blocks: the states carry the rigid bricks too ({nsol} hexahedra of {len(parts)} parts; "
           f"expected 24 x 16 + 64 of 25)", nsol == 24 * 16 + 64 and parts == set(range(1, 26)))
    worst, crossings, nstate, t_worst = penetration.check_run(out)
    record(f"wall of blocks: largest penetration {worst:.1%} of the local thickness (under 20%) at "
           f"{t_worst * 1e3:.1f} ms, pass-throughs {crossings} (0), {nstate} states", worst < 0.2 and crossings == 0)
    ke0 = g["kinetic_energy"][0]
    smin = g["sliding_interface_energy"].min()
    record(f"wall of blocks: frictionless contact does no net positive work (lowest sliding energy "
           f"{smin / ke0:+.2e} of the initial kinetic energy, not below -1e-3)", smin >= -1e-3 * ke0)
    record(f"wall of blocks: kinetic energy at the end {g['kinetic_energy'][-1]:.1f} J, at most the initial "
           f"{ke0:.1f} J", g["kinetic_energy"][-1] <= ke0 * (1 + 1e-9))
    # d3hsp's contact table by part pair: the work of all pairs is minus the
    # sliding energy (glstat's last value lacks at most the second half of
    # the last cycle's contact work: 1% of the largest sliding energy)
    m = re.search(r"all pairs\s+(\S+)\s+(\S+)", open(os.path.join(out, "d3hsp")).read())
    smax = abs(g["sliding_interface_energy"]).max()
    wsum = float(m.group(2)) if m else float("nan")
    record(f"wall of blocks: the contact's work by part pair in d3hsp sums to minus the sliding energy "
           f"({wsum:.4f} J against {-g['sliding_interface_energy'][-1]:.4f} J, within 1% of {smax:.2f} J)",
           abs(wsum + g["sliding_interface_energy"][-1]) <= 0.01 * smax)
