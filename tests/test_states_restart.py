"""States (d3plot.h5, the XDMF, the d3plot family read by VTK) and restarts.

Each check states its tolerance and why (tests/README.md: how to run
and add tests)."""
from xdtest import *  # noqa: F401,F403 (the shared helpers and imports)


def test_states():
    """States (*DATABASE_BINARY_D3PLOT) of a deck with solids and shells
    (a plate edge-on onto a block, through contact), every 0.1 ms over
    0.5 ms: d3plot.h5 read back with h5py (the right shapes; coordinates =
    initial coordinates + displacement to single precision, the storage;
    the first state's coordinates are the deck's; element stresses finite;
    contact forces present while the plate touches) and d3plot.xdmf parsed
    as XML, every HDF5 path in it resolving to a dataset of the stated
    dimensions. Then tools/xdplot.py writes non-empty PNGs from the run."""
    import xml.etree.ElementTree as ET
    src = open(os.path.join(ROOT, "input_decks/contact/shell_edge_on_solid.k")).read()
    deck = os.path.join(TMP, "states.k")
    with open(deck, "w") as fh:
        fh.write(src.replace("*DATABASE_NODOUT", "*DATABASE_BINARY_D3PLOT\n    1.0e-4\n*DATABASE_NODOUT", 1))
    out = os.path.join(TMP, "states")
    p = run([XDYNA, "i=" + deck, "outdir=" + out, "endtim=5.0e-4"])
    if p.returncode != 0:
        record("states run", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
        t = f["states/time"][:]
        ids = f["mesh/node_ids"][:]
        nn, nh, ns = len(ids), len(f["mesh/shell_ids"]), len(f["mesh/solid_ids"])
        ok_shape, err_x, fmax, finite = True, 0.0, 0.0, True
        x0 = f["states/000001/coordinates"][:]
        for k in range(len(t)):
            g = f[f"states/{k + 1:06d}"]
            for name, shape in (("coordinates", (nn, 3)), ("displacement", (nn, 3)), ("velocity", (nn, 3)),
                                ("contact_force", (nn, 3)), ("solid_stress", (ns, 6)), ("solid_von_mises", (ns,)),
                                ("solid_plastic_strain", (ns,)), ("shell_stress", (nh, 6)),
                                ("shell_von_mises", (nh,)), ("shell_plastic_strain", (nh,)),
                                ("shell_thickness", (nh,))):
                ok_shape = ok_shape and name in g and g[name].shape == shape
            scale = np.abs(x0).max()
            err_x = max(err_x, np.abs(g["coordinates"][:] - (x0 + g["displacement"][:])).max() / scale)
            fmax = max(fmax, np.abs(g["contact_force"][:]).max())
            finite = finite and np.all(np.isfinite(g["solid_stress"][:])) and np.all(np.isfinite(g["shell_stress"][:]))
            ok_shape = ok_shape and abs(g.attrs["time"][0] - t[k]) == 0.0
        conn_ok = (f["mesh/solid_connectivity"][:].max() < nn and f["mesh/shell_connectivity"][:].max() < nn
                   and f["mesh/solid_connectivity"][:].min() >= 0)
        deck_x = {}
        for line in src.split("*NODE", 1)[1].split("*", 1)[0].splitlines()[1:]:
            if line.strip() and not line.startswith("$"):
                deck_x[int(line[:8])] = [float(line[8:24]), float(line[24:40]), float(line[40:56])]
        x_deck = np.array([deck_x[i] for i in ids])
        e0 = np.abs(x0 - x_deck).max() / scale
        paths = []
        root = ET.parse(os.path.join(out, "d3plot.xdmf")).getroot()
        for item in root.iter("DataItem"):
            fn, path = item.text.strip().split(":", 1)
            dims = tuple(int(d) for d in item.get("Dimensions").split())
            paths.append(fn == "d3plot.h5" and path in f and f[path].shape == dims)
        nxdmf = sum(1 for g in root.iter("Grid") if g.get("CollectionType") == "Spatial")
        # the deck's ids as attributes of every block: node ids on the nodes,
        # element ids on the cells, the same sets as the deck's
        deck_shell = set()
        for line in src.split("*ELEMENT_SHELL", 1)[1].split("*", 1)[0].splitlines()[1:]:
            if line.strip() and not line.startswith("$"):
                deck_shell.add(int(line[:8]))
        deck_solid = set()
        for line in src.split("*ELEMENT_SOLID", 1)[1].split("*", 1)[0].splitlines()[1:]:
            if line.strip() and not line.startswith("$"):
                deck_solid.add(int(line[:8]))
        id_ok, nid = True, 0
        for g in root.iter("Grid"):
            if g.get("GridType") != "Uniform":
                continue
            at = {a.get("Name"): a for a in g.iter("Attribute")}
            if "node_id" not in at or "element_id" not in at:
                id_ok = False
                continue
            nid += 1
            nv = f[at["node_id"].find("DataItem").text.strip().split(":", 1)[1]][:]
            ev = f[at["element_id"].find("DataItem").text.strip().split(":", 1)[1]][:]
            want = deck_solid if g.get("Name") == "solids" else deck_shell
            id_ok = (id_ok and at["node_id"].get("Center") == "Node" and at["element_id"].get("Center") == "Cell"
                     and set(nv.tolist()) == set(deck_x) and set(ev.tolist()) == want)
    record(f"states: every block of d3plot.xdmf carries the deck's node ids on its nodes and element ids on "
           f"its cells ({nid} blocks)", id_ok and nid == 2 * len(t))
    record(f"states: {len(t)} states at 0.1 ms over 0.5 ms (6 expected), increasing times", len(t) == 6
           and np.all(np.diff(t) > 0) and abs(t[-1] - 5e-4) < 1e-5)
    record("states: every dataset of every state has the right shape; element stresses finite; connectivity "
           "indexes the node arrays", ok_shape and finite and conn_ok)
    record(f"states: coordinates = initial + displacement within single precision ({err_x:.1e} of the size, "
           f"< 1e-6); the first state is the deck's geometry ({e0:.1e})", err_x < 1e-6 and e0 < 1e-6)
    record(f"states: the contact force appears in the states while the plate touches ({fmax:.3g} N)", fmax > 0)
    record(f"states: d3plot.xdmf is XML with {nxdmf} time steps; all {len(paths)} data paths resolve to "
           f"datasets of the stated dimensions", nxdmf == len(t) and len(paths) > 0 and all(paths))
    if shutil.which("pvpython"):
        # ParaView's own XDMF reader, where Debian's paraview is installed
        # (make deps does not install it: it is large); skipped otherwise
        q = run(["pvpython", os.path.join(ROOT, "tools", "xdmf_check.py"), os.path.join(out, "d3plot.xdmf")])
        lines = [x for x in q.stdout.splitlines() if x.startswith(("time steps", "block"))]
        good = (q.returncode == 0 and lines and lines[0].startswith("time steps 6 ")
                and sum(1 for x in lines if x.startswith("block")) == 2)
        record("states: ParaView (pvpython) reads d3plot.xdmf as a time series of 6 steps with the solid "
               "and shell blocks", good, q.stdout[-300:] + q.stderr[-300:])
    else:
        skip("states: pvpython is not installed (Debian's paraview); the XDMF was checked with h5py only")
    pngs = []
    for args in (["mesh", out, "--color", "von_mises"], ["mesh", out], ["history", out, out, "--nodes", "1"]):
        png = os.path.join(TMP, f"states_{len(pngs)}.png")
        q = run(["/usr/bin/python3", os.path.join(ROOT, "tools", "xdplot.py"), *args, "--out", png])
        pngs.append(q.returncode == 0 and os.path.exists(png) and os.path.getsize(png) > 10000)
    record("plotting: tools/xdplot.py writes deformed-mesh (by field, by part) and overlaid history PNGs "
           "(each over 10 kB)", all(pngs))
    # a default run writes no d3plot.h5: the tools read the binary d3plot
    # family (tools/d3plot_read.py), which holds the run's own values (the
    # float32 of d3plot.h5's, compared exactly); xdplot's mesh then works
    # (it stopped with "d3plot.h5 not found" before)
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    from d3plot_read import D3plot
    d = D3plot(out)
    worst, nst = 0.0, 0
    with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
        same_t = np.array_equal(d.times.astype(np.float32), f["states/time"][:].astype(np.float32))
        for k in range(len(d.times)):
            a, g = d.state(k), f[f"states/{k + 1:06d}"]
            for q in ("coordinates", "shell_plastic_strain", "shell_thickness", "solid_plastic_strain"):
                if q in g:
                    worst = max(worst, float(np.abs(a[q] - g[q][:].astype(np.float32)).max()))
            nst += 1
    plain = out + "_binary_only"
    shutil.copytree(out, plain, dirs_exist_ok=True)
    os.remove(os.path.join(plain, "d3plot.h5"))
    png = os.path.join(TMP, "states_binary.png")
    q = run(["/usr/bin/python3", os.path.join(ROOT, "tools", "xdplot.py"), "mesh", plain, "--color", "plastic_strain",
             "--out", png])
    record(f"plotting: without d3plot.h5 the tools read the d3plot family ({nst} states, times and fields equal to "
           f"d3plot.h5's, largest difference {worst:.1e}) and xdplot.py mesh writes its PNG",
           same_t and nst == len(d.times) and nst > 1 and worst == 0.0 and q.returncode == 0
           and os.path.exists(png) and os.path.getsize(png) > 10000, q.stderr[-300:])


def deck_part_titles(deck):
    """{part id: heading} of a deck's *PART cards (the heading card, then
    the card whose first field is the id)."""
    lines = [x for x in open(deck).read().splitlines() if not x.startswith("$")]
    out = {}
    for i, x in enumerate(lines):
        if x.strip().upper() == "*PART":
            out[int(lines[i + 2].replace(",", " ").split()[0])] = lines[i + 1].strip()
    return out


def dump_sum(data):
    """The checksum xdyna writes after a dump's bytes (restart.f90,
    image_sum): Adler's two sums modulo 2^31 - 1, b * 2^31 + a."""
    p = 2147483647
    x = np.frombuffer(data, dtype=np.uint8).astype(np.int64)
    n = len(x)
    a = (1 + int(x.sum())) % p
    # b = sum over i of a_i = n + sum_i (n - i) x_i, i from 0
    b = (n + int(np.dot(np.arange(n, 0, -1, dtype=np.int64) % p, x) % p)) % p if n else 0
    return b * 2147483648 + a


def unseal_dump(path):
    """Cut the checksum record off a dump (to edit it with h5py)."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[-16:-8] == b"XDYNASUM"
    with open(path, "wb") as f:
        f.write(data[:-16])


def seal_dump(path):
    """Append the checksum record a dump ends with."""
    with open(path, "rb") as f:
        data = f.read()
    with open(path, "ab") as f:
        f.write(b"XDYNASUM" + int(dump_sum(data)).to_bytes(8, "little", signed=True))


def test_d3plot():
    """The d3plot family in LS-DYNA's binary layout, opened by an independent
    reader: VTK's vtkLSDynaReader (Debian's python3-vtk9; SKIP where it is
    absent). Two runs, each also writing d3plot.h5, whose values are the
    run's own: the square tube crushed with self-contact to 2.5 ms (six
    states, x=1 so that the family splits into members), and a solid block
    with a shell plate and a rigid block (three parts, ids in another order
    than the d3plot's materials). Held exactly (both files store float32 of
    the same numbers): the number of states, every time, the solid
    stress and plastic strain, the shell thickness and largest plastic
    strain; every element's corners at the coordinates of its nodes in every state
    (VTK's cells against the deck's connectivity: every node is a corner);
    the shell stress through the thickness (VTK's five layers,
    weighted by the Gauss weights) against d3plot.h5's mean stress to 2e-6
    of the largest stress (float32 round-off of a sum of five rotated
    tensors); every part block holds exactly the deck part's elements. The
    default run (no h5plot) writes the family alone, the same bytes."""
    try:
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy as v2n
    except ImportError:
        skip("d3plot: VTK's LS-DYNA reader (Debian's python3-vtk9) is not installed")
        return
    gw5 = np.array([0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                    0.2369268850561891]) / 2
    cases = [("tube", "input_decks/contact/tube_crush.k", ("endtim=2.5e-3", "x=1"), ""),
             ("mixed", "input_decks/verify/mixed_solid_shell_rigid.k", (),
              "*DATABASE_BINARY_D3PLOT\n    2.0e-4\n")]
    for name, src, extra, cards in cases:
        deck = with_cards(src, "d3plot_" + name, cards) if cards else os.path.join(ROOT, src)
        out = os.path.join(TMP, "d3plot_" + name)
        shutil.rmtree(out, ignore_errors=True)
        p = run([XDYNA, "i=" + deck, "outdir=" + out, "h5plot=1", *extra])
        if p.returncode != 0:
            record(f"d3plot {name}: run", False, p.stderr[-300:])
            continue
        members = sorted(x for x in os.listdir(out) if re.fullmatch(r"d3plot(\d\d+)?", x))
        r = vtk.vtkLSDynaReader()
        r.SetDatabaseDirectory(out)
        r.UpdateInformation()
        with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
            t = f["states/time"][:]
            ids = f["mesh/node_ids"][:]
            row = {int(n): i for i, n in enumerate(ids)}
            nstate = r.GetNumberOfTimeSteps()
            times = [r.GetTimeValue(k) for k in range(nstate)]
            same_t = nstate == len(t) and np.array_equal(np.array(times), t.astype(np.float32).astype(float))
            # per quantity: the largest difference and the largest value met
            # (a check that met only zeros would measure nothing)
            worst = {q: [0.0, 0.0] for q in ("coordinates", "solid stress", "solid plastic strain", "shell thickness",
                                             "shell plastic strain", "shell stress")}

            def held(q, ours, ref):
                worst[q][0] = max(worst[q][0], float(np.abs(ours - ref).max()))
                worst[q][1] = max(worst[q][1], float(np.abs(ref).max()))
            parts_ok, nseen, ncells = True, 0, 0
            titles_ok, named = True, []
            heads = deck_part_titles(deck)
            covered = set()
            eparts = {}
            for kind in ("solid", "shell"):
                if f"mesh/{kind}_ids" in f:
                    for e, q in zip(f[f"mesh/{kind}_ids"][:], f[f"mesh/{kind}_part"][:]):
                        eparts.setdefault(int(q), set()).add((kind, int(e)))
            for k in range(min(nstate, len(t))):
                g = f[f"states/{k + 1:06d}"]
                x = g["coordinates"][:]
                r.SetTimeStep(k)
                r.Update()
                for bname, b in vtk_blocks(r):
                    # VTK 9.1 reads the node ids of 32-bit files two to a
                    # 64-bit value: the nodes are matched through the
                    # elements (their ids read right), whose corners must be
                    # the deck connectivity's nodes at d3plot.h5's positions
                    cd = b.GetCellData()
                    eid = v2n(cd.GetArray("UserIds"))
                    kind = "solid" if b.GetCellType(0) == vtk.VTK_HEXAHEDRON else "shell"
                    npe = 8 if kind == "solid" else 4
                    erow = {int(e): i for i, e in enumerate(f[f"mesh/{kind}_ids"][:])}
                    rows = [erow[int(e)] for e in eid]
                    pts = v2n(b.GetPoints().GetData())
                    corner = pts[v2n(b.GetCells().GetConnectivityArray()).reshape(-1, npe)]
                    conn = f[f"mesh/{kind}_connectivity"][:][rows]
                    held("coordinates", corner, x[conn])
                    if k == 0:
                        covered.update(int(n) for n in conn.ravel())
                    if k == 0:
                        nseen += 1
                        ncells += len(eid)
                        mine = {(kind, int(e)) for e in eid}
                        owner = [q for q, es in eparts.items() if es == mine]
                        parts_ok = parts_ok and len(owner) == 1
                        # the block's name is its part's title (the d3plot's
                        # part-title section; before: "PartK (MatlM)")
                        named.append(bname)
                        titles_ok = titles_ok and len(owner) == 1 and bname == heads.get(owner[0])
                    if kind == "solid":
                        held("solid stress", v2n(cd.GetArray("Stress")), g["solid_stress"][:][rows])
                        held("solid plastic strain", v2n(cd.GetArray("EffPlastStrn")),
                             g["solid_plastic_strain"][:][rows])
                    else:
                        held("shell thickness", v2n(cd.GetArray("Thickness")), g["shell_thickness"][:][rows])
                        # five points: written in their order from the bottom;
                        # three: mid-surface, inner, outer (LS-DYNA's MAXINT 3)
                        if cd.GetArray("StressIntPt5") is not None:
                            names, w = ["", "InnerSurf", "OuterSurf", "IntPt4", "IntPt5"], gw5
                        else:
                            names, w = ["", "InnerSurf", "OuterSurf"], np.array([8.0, 5.0, 5.0]) / 18
                        lay = [v2n(cd.GetArray("Stress" + s)).astype(float) for s in names]
                        held("shell stress", sum(wi * si for wi, si in zip(w, lay)), g["shell_stress"][:][rows])
                        eps = np.max([v2n(cd.GetArray("EffPlastStrn" + s)) for s in names], axis=0)
                        held("shell plastic strain", eps, g["shell_plastic_strain"][:][rows])
        nel = sum(len(v) for v in eparts.values())
        exact = all(v[0] == 0.0 for key, v in worst.items() if key != "shell stress")
        stress_ok = worst["shell stress"][0] <= 2e-6 * max(worst["shell stress"][1], 1.0)
        # what each deck must exercise: the tube yields, the mixed deck has
        # solids; both have shells under stress
        met = worst["shell stress"][1] > 0 and worst["coordinates"][1] > 0 and (
            worst["shell plastic strain"][1] > 0 if name == "tube" else worst["solid stress"][1] > 0)
        record(f"d3plot {name}: vtkLSDynaReader reads {nstate} states in {len(members)} member(s) ({' '.join(members)}), "
               f"the times, the coordinates of every element corner ({len(covered)} of {len(ids)} nodes) in every "
               f"state, solid stress and plastic strain, shell "
               f"thickness and plastic strain equal to the run's own (d3plot.h5) "
               f"(difference / largest value: {', '.join(f'{k2} {v[0]:.1e} / {v[1]:.3g}' for k2, v in worst.items())}); "
               f"{nseen} part blocks of {ncells} cells, "
               f"each exactly one deck part's elements ({nel} elements) and named by the deck's part title ({named})",
               same_t and exact and stress_ok and met and parts_ok and titles_ok and ncells == nel and nstate == len(t)
               and len(covered) == len(ids)
               and (name != "tube" or len(members) > 1))
        if name == "mixed":
            # the default: the family alone, the same bytes
            q = run([XDYNA, "i=" + deck, "outdir=" + out + "_default"], env={"XDYNA_H5PLOT": "0"})
            same = q.returncode == 0 and not os.path.exists(os.path.join(out + "_default", "d3plot.h5")) and \
                open(os.path.join(out, "d3plot"), "rb").read() == open(os.path.join(out + "_default", "d3plot"), "rb").read()
            record("d3plot: the default run writes the d3plot family alone (no d3plot.h5), byte for byte the same", same)


def test_restart():
    """Restart dumps (*DATABASE_BINARY_D3DUMP) and r=: for a contact deck
    with solids and shells, two plates in edge-to-edge contact (the dump
    in the middle of it), a deck with a rigid part under gravity, a bar
    against a moving rigid wall and a spot weld that fails, the run to T
    and the run to T/2 restarted to T give time histories that thdiff
    passes at zero tolerance, with the same rows (the restart cuts the
    histories back to the dump and goes on) and the same ASCII files; the
    states file goes on too. A changed deck and a dump of another build are
    refused (exit 1)."""
    cases = [("input_decks/contact/shell_edge_on_solid.k", 1.0e-3),
             ("input_decks/contact/crossed_edges_general.k", 4.0e-5),
             ("input_decks/verify/mixed_solid_shell_rigid_gravity.k", 2.0e-3),
             ("input_decks/verify/bar_heavy_wall.k", None),
             ("input_decks/verify/spot_weld_fail.k", None),
             ("input_decks/verify/shell_pinch_mass_scaling.k", None)]
    for src, endtim in cases:
        name = os.path.splitext(os.path.basename(src))[0]
        if endtim is None:
            for line in open(os.path.join(ROOT, src)).read().split("*CONTROL_TERMINATION\n", 1)[1].splitlines()[:1]:
                endtim = float(line[:10])
        deck = with_cards(src, "rs_" + name, "*DATABASE_BINARY_D3DUMP\n         0\n*DATABASE_BINARY_D3PLOT\n"
                          f"{endtim / 10:10.4g}\n")
        full, part = os.path.join(TMP, "rs_full_" + name), os.path.join(TMP, "rs_part_" + name)
        p1 = run([XDYNA, "i=" + deck, "outdir=" + full, f"endtim={endtim!r}"])
        p2 = run([XDYNA, "i=" + deck, "outdir=" + part, f"endtim={endtim / 2!r}"])
        p3 = run([XDYNA, "r=" + os.path.join(part, "d3dump.h5"), f"endtim={endtim!r}"])
        if p1.returncode or p2.returncode or p3.returncode:
            record(f"restart {name} runs", False, (p1.stderr + p2.stderr + p3.stderr)[-300:])
            continue
        ok, msg = same_histories(full, part)
        with h5py.File(os.path.join(full, "d3plot.h5"), "r") as fa, h5py.File(os.path.join(part, "d3plot.h5"), "r") as fb:
            ta, tb = fa["states/time"][:], fb["states/time"][:]
            states = np.array_equal(ta, tb) and all(
                np.array_equal(fa[f"states/{k:06d}/coordinates"][:], fb[f"states/{k:06d}/coordinates"][:])
                for k in range(1, len(ta) + 1))
        # the d3plot family: the restart cuts it back to the dump's states and
        # goes on, so that every member reads the same bytes
        fam = lambda d: sorted(os.path.basename(x) for x in glob.glob(os.path.join(d, "d3plot*"))
                               if not x.endswith((".h5", ".xdmf")))
        binary = fam(full) == fam(part) and len(fam(full)) > 0 and all(
            open(os.path.join(full, m), "rb").read() == open(os.path.join(part, m), "rb").read() for m in fam(full))
        states = states and binary
        record(f"restart {name}: run to T/2 and restarted gives the run to T bitwise (thdiff at zero "
               f"tolerance, same rows, same ASCII files, same {len(ta)} states, the same {len(fam(full))} d3plot "
               f"member(s) byte for byte)", ok and states, msg)
    # refusals, on the last case's dump
    dump = os.path.join(part, "d3dump.h5")
    changed = os.path.join(TMP, "rs_changed.k")
    with open(changed, "w") as fh:
        fh.write(open(deck).read().replace("*KEYWORD\n", "*KEYWORD\n$ an edit after the dump\n", 1))
    q = run([XDYNA, "r=" + dump, "i=" + changed])
    record("restart: a deck changed since the dump is refused (exit 1, says so)",
           q.returncode == 1 and "has changed since the dump" in q.stderr, q.stderr[-200:])
    other = os.path.join(TMP, "rs_other_build.h5")
    shutil.copy(dump, other)
    # (a dump ends with a checksum of its bytes: edited as another build's
    # would be written, then sealed again as that build would seal it)
    unseal_dump(other)
    with h5py.File(other, "r+") as f:
        del f.attrs["build"]
        f.attrs.create("build", np.bytes_("xdyna 0.0.9, real 32 bits, another compiler"))
    seal_dump(other)
    q = run([XDYNA, "r=" + other])
    record("restart: a dump of another build is refused (exit 1, names both builds)",
           q.returncode == 1 and "another build" in q.stderr, q.stderr[-200:])
