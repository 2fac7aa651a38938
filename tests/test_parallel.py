"""Threads and MPI ranks: the same answers for any count, decompositions, owned
nodes, contact ghosts, stack limits.

Each check states its tolerance and why (tests/README.md: how to run
and add tests)."""
import pytest

from xdtest import *  # noqa: F401,F403 (the shared helpers and imports)


@pytest.mark.slow(30)
def test_threads():
    """Force assembly is deterministic: 1 and 2 threads give bitwise equal
    histories; with contact, 1, 2 and 4 threads."""
    p1, o1 = run_deck("input_decks/verify/prestressed_block.k", "threads1", env={"OMP_NUM_THREADS": "1"})
    p2, o2 = run_deck("input_decks/verify/prestressed_block.k", "threads2", env={"OMP_NUM_THREADS": "2"})
    q = run([THDIFF, o1, o2, "--rtol", "0", "--atol", "0"])
    record("OMP_NUM_THREADS 1 and 2 give bitwise identical time histories", q.returncode == 0, q.stdout[-300:])
    # with contact (issue 8): the shells, the global search (slave blocks
    # joined in order), the local search and the per-slave penalty forces run
    # threaded; the pairs are listed and their forces summed in slave order.
    # 4 threads on this 2-core machine are oversubscribed, which changes the
    # threads' timing, not the result
    for deck, name, endtim in (("input_decks/contact/tube_crush.k", "tube crush", "0.0015"),
                               ("input_decks/paper/wall_of_blocks.k", "wall of blocks", "0.01")):
        runs = [run_deck(deck, f"threads_c{n}", env={"OMP_NUM_THREADS": str(n)}, extra=(f"endtim={endtim}",))
                for n in (1, 2, 4)]
        qs = [run([THDIFF, runs[0][1], o, "--rtol", "0", "--atol", "0"]) for _, o in runs[1:]]
        record(f"{name} with contact: OMP_NUM_THREADS 1, 2 and 4 give bitwise identical time histories",
               all(p.returncode == 0 for p, _ in runs) and all(q.returncode == 0 for q in qs),
               " ".join(q.stdout[-200:] for q in qs))
    # a run started without a launcher does not start MPI (its start and
    # finish cost 0.4 s a run): the one-rank operations in its place give
    # Open MPI's lone rank (XDYNA_MPI=1) bit for bit, and d3hsp says which
    a, oa = run_deck("input_decks/contact/tube_crush.k", "lone_nompi", env={"OMP_NUM_THREADS": "1"},
                     extra=("endtim=0.0015",))
    b, ob = run_deck("input_decks/contact/tube_crush.k", "lone_mpi", env={"OMP_NUM_THREADS": "1", "XDYNA_MPI": "1"},
                     extra=("endtim=0.0015",))
    q = run([THDIFF, oa, ob, "--rtol", "0", "--atol", "0"])
    la = open(os.path.join(oa, "d3hsp")).read()
    lb = open(os.path.join(ob, "d3hsp")).read()
    record("a lone run without MPI gives the lone MPI rank's (XDYNA_MPI=1) histories bitwise, d3hsp saying which",
           a.returncode == 0 and b.returncode == 0 and q.returncode == 0 and "MPI not started" in la
           and "MPI not started" not in lb and " ranks 1, threads per rank 1" in lb, q.stdout[-200:])


def domain_table(out):
    """The d3hsp decomposition table: {rank: (cost, slaves, [part ids])}."""
    rows, on = {}, False
    for line in open(os.path.join(out, "d3hsp")).read().splitlines():
        if "d o m a i n   d e c o m p o s i t i o n" in line:
            on = True
        elif on and re.match(r"^\s+\d+\s+[\d.]+\s+[\d.]+\s+\d+", line):
            f = line.split()
            rows[int(f[0])] = (float(f[1]), int(f[3]), [int(x) for x in f[4:] if x != "none"])
        elif on and "halo" in line:
            break
    return rows


@pytest.mark.slow(171)
def test_mpi():
    """MPI domain decomposition (issue 8). Every node's force is summed in
    the serial slot order and the contacts in slave order, so the motion is
    the serial run's bit for bit for 1, 2 and 4 ranks (oversubscribed on
    this 2-core machine, which changes timing only). These models run with
    owned nodes (issue 32), whose energies, momenta and mean velocities are
    each rank's sums added over the ranks: those agree to rounding
    (same_dynamics: 1e-12 of their scale), every other series bitwise."""
    if mpi_missing():
        return
    cases = [("solids: Taylor bar (972 hexahedra)", "input_decks/verify/taylor_bar_coarse.k", ()),
             ("shells with self-contact: tube crush", "input_decks/contact/tube_crush.k", ("endtim=0.0015",)),
             ("rigid wall, rigid bodies, shells and contact: front frame", "input_decks/paper/front_frame.k",
              ("endtim=0.003",)),
             ("solid against a moving rigid wall", "input_decks/verify/bar_heavy_wall.k", ()),
             ("rigid bricks in contact: wall of blocks", "input_decks/paper/wall_of_blocks.k", ("endtim=0.01",))]
    for label, deck, extra in cases:
        name = os.path.splitext(os.path.basename(deck))[0]
        p0, serial = run_deck(deck, "mpi_serial_" + name, extra=extra)
        for n in (1, 2, 4):
            out = os.path.join(TMP, f"mpi{n}_{name}")
            p = mpirun(n, ["i=" + os.path.join(ROOT, deck), "outdir=" + out, *extra])
            ok, msg = (False, p.stderr[-300:]) if p.returncode or p0.returncode else same_dynamics(serial, out)
            spread = True
            if n == 2 and ok:
                # both ranks have work: elements or slave nodes (on 4 ranks a
                # small model may leave a rank idle: the solid groups of 128
                # elements are the unit of the split)
                t = domain_table(out)
                spread = len(t) == n and all(c > 0 or s > 0 for c, s, _ in t.values())
            record(f"MPI {label}: mpirun -np {n} gives the serial run's motion bitwise, its energies to 1e-12",
                   ok and spread,
                   msg + f" rc={p.returncode}")
    # the frame's states too: every dataset of d3plot.h5 equal
    with h5py.File(os.path.join(TMP, "mpi_serial_front_frame", "d3plot.h5"), "r") as fa, \
            h5py.File(os.path.join(TMP, "mpi4_front_frame", "d3plot.h5"), "r") as fb:
        names = []
        fa.visititems(lambda k, v: names.append(k) if isinstance(v, h5py.Dataset) else None)
        same = all(k in fb and np.array_equal(fa[k][()], fb[k][()]) for k in names)
    record(f"MPI front frame: d3plot.h5 of 4 ranks equals the serial one ({len(names)} datasets, bitwise)", same)
    fa, fb = (os.path.join(TMP, d, "d3plot") for d in ("mpi_serial_front_frame", "mpi4_front_frame"))
    same = os.path.exists(fa) and os.path.exists(fb) and open(fa, "rb").read() == open(fb, "rb").read()
    record(f"MPI front frame: the d3plot of 4 ranks equals the serial one byte for byte "
           f"({os.path.getsize(fa) if os.path.exists(fa) else 0} bytes)", same)

    # contact found across the partition boundary: the two bars of
    # two_bars_penalty.k lie on different ranks (each rank's elements are one
    # part), so their only contact is between ranks; each bar's momentum
    # turns round (the contact was found and acted), and the histories are
    # the serial run's, bitwise
    deck = "input_decks/contact/two_bars_penalty.k"
    p0, serial = run_deck(deck, "mpi_serial_bars")
    out = os.path.join(TMP, "mpi2_bars")
    p = mpirun(2, ["i=" + os.path.join(ROOT, deck), "outdir=" + out])
    t = domain_table(out) if p.returncode == 0 else {}
    apart = len(t) == 2 and len(t[0][2]) == 1 and len(t[1][2]) == 1 and t[0][2] != t[1][2]
    ok, msg = same_dynamics(serial, out) if p.returncode == 0 else (False, p.stderr[-300:])
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        m = f["matsum/x_momentum"][:]
    turned = m.shape[1] == 2 and m[0, 0] * m[-1, 0] < 0 and m[0, 1] * m[-1, 1] < 0
    record(f"MPI contact across ranks: bars (parts {t.get(0, (0, 0, []))[2]} and {t.get(1, (0, 0, []))[2]}) on "
           f"different ranks bounce (x momentum {m[0, 0]:.4g} -> {m[-1, 0]:.4g}), the serial run's motion bitwise",
           apart and ok and turned, msg)

    # the Lagrangian projection across ranks: the torture suite's aligned
    # bars (40 elements, node-to-surface) and a rigid corner on a face, on
    # 2 and 4 ranks, the replicated state bitwise and owned nodes' motion
    # bitwise (the projection reads every pair's gap, which the ranks had
    # not passed on: both states had parted from the serial run, the bars'
    # internal energy by 22 of 31 J)
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import contact_suite as cs
    g = cs.g
    picked = {c["name"]: c for c in cs.cases()}
    for name in ("bars_nts_lag_node_1to1_k1_v10_n40", "corner_on_face_single_lag_node_1to1_k1_v10_rotx15"):
        c = picked[name]
        lines, _ = cs.FAMILIES[c["family"]](c)
        deck = os.path.join(TMP, "lag_" + name + ".k")
        g.write(deck, lines)
        serial = os.path.join(TMP, "lag_serial_" + name)
        p0 = run([XDYNA, "i=" + deck, "outdir=" + serial])
        for n in (2, 4):
            for state, env in (("owned nodes", "0"), ("replicated", "1")):
                out = os.path.join(TMP, f"lag{n}{env}_" + name)
                q = mpirun(n, ["i=" + deck, "outdir=" + out], env_extra={"XDYNA_REPLICATED": env})
                ok, msg = ranks_match(serial, out) if not (q.returncode or p0.returncode) else (False, q.stderr[-300:])
                record(f"MPI Lagrangian contact, {c['family']} ({name}): {n} ranks, {state}, give the serial run "
                       f"({'bitwise' if env == '1' else 'its motion bitwise'})", ok, msg)

    # MPI x OpenMP: 2 ranks of 2 threads
    deck = "input_decks/contact/tube_crush.k"
    out = os.path.join(TMP, "mpi2x2_tube")
    p = mpirun(2, ["i=" + os.path.join(ROOT, deck), "outdir=" + out, "endtim=0.0015"], threads=2)
    ok, msg = same_dynamics(os.path.join(TMP, "mpi_serial_tube_crush"), out) if p.returncode == 0 \
        else (False, p.stderr[-300:])
    record("MPI x OpenMP: 2 ranks x 2 threads on the tube crush give the serial run's motion bitwise", ok, msg)

    # restart under MPI: dump from 2 ranks at T/2, go on to T on 4 ranks; the
    # serial run to T, bitwise (the dump holds every rank's elements and slaves)
    src, endtim = "input_decks/contact/shell_edge_on_solid.k", 1.0e-3
    deck = with_cards(src, "mpi_rs", "*DATABASE_BINARY_D3DUMP\n         0\n")
    full, part = os.path.join(TMP, "mpi_rs_full"), os.path.join(TMP, "mpi_rs_part")
    p1 = run([XDYNA, "i=" + deck, "outdir=" + full, f"endtim={endtim!r}"])
    p2 = mpirun(2, ["i=" + deck, "outdir=" + part, f"endtim={endtim / 2!r}"])
    p3 = mpirun(4, ["r=" + os.path.join(part, "d3dump.h5"), f"endtim={endtim!r}"])
    ok, msg = same_dynamics(full, part) if not (p1.returncode or p2.returncode or p3.returncode) \
        else (False, (p2.stderr + p3.stderr)[-300:])
    record("MPI restart: dumped on 2 ranks at T/2, restarted on 4 to T, gives the serial run's motion to T bitwise",
           ok, msg)

    # batch under MPI: the wall-clock guard stops every rank at the same cycle
    # with a dump (exit 3; the ranks take the largest of their flags each
    # cycle); the restart on 2 ranks ends as the uninterrupted serial run
    deck = os.path.join(ROOT, "input_decks/contact/tube_crush.k")
    p0, serial = run_deck("input_decks/contact/tube_crush.k", "mpi_wc_serial")
    out = os.path.join(TMP, "mpi_wc")
    p1 = mpirun(2, ["i=" + deck, "outdir=" + out, "wallclock=1.5"])
    p2 = mpirun(2, ["r=" + os.path.join(out, "d3dump.h5")]) if p1.returncode == 3 else p1
    ok, msg = same_dynamics(serial, out) if p2.returncode == 0 and p0.returncode == 0 else (False, p1.stderr[-300:])
    record("MPI wall-clock stop: 2 ranks stop together with a dump (exit 3), the restart on 2 ranks ends as the "
           "serial run (its motion bitwise)", p1.returncode == 3 and ok, f"rc={p1.returncode} {msg}")

    # errors under MPI: an input error is reported once, exit 1; a run gone
    # bad stops every rank with exit 2 and the diagnostic
    p = mpirun(2, ["i=" + os.path.join(ROOT, "tests/decks/malformed/bad_number.k"),
                   "outdir=" + os.path.join(TMP, "mpi_bad")])
    record("MPI input error: exit 1, the message once", p.returncode == 1 and p.stderr.count("bad_number.k") == 1,
           f"rc={p.returncode} {p.stderr[-300:]}")
    p = mpirun(2, ["i=" + os.path.join(ROOT, "tests/decks/runtime/negative_volume.k"),
                   "outdir=" + os.path.join(TMP, "mpi_negvol")])
    # (the crushed hexahedron's stop names the element or its node: see
    # test_runtime_error)
    record("MPI run gone bad: exit 2 naming solid 42 (or its node 7) of part 17, once",
           p.returncode == 2 and p.stderr.count("negative volume in solid 42 of part 17")
           + p.stderr.count("node 7 (part 17)") == 1, f"rc={p.returncode} {p.stderr[-300:]}")


def test_mpi_metis():
    """decomp=metis (issue 32): the elements split by METIS's k-way
    partition of their graph instead of coordinate bisection. The motion
    depends on no decomposition (every node's force is summed in the serial
    slot order, the contacts in slave order), so 2 and 4 ranks give the
    serial run's motion bitwise and its energies to 1e-12 (same_dynamics);
    the parts are balanced within METIS's 3% imbalance (ufactor 30) plus
    the rounding of the costs to tenths: at most 1.05 of the mean; a value
    other than rcb or metis is an input error naming it."""
    if mpi_missing():
        return
    cases = [("shells with self-contact: tube crush", "input_decks/contact/tube_crush.k", ("endtim=0.0015",)),
             ("rigid wall, rigid bodies, shells and contact: front frame", "input_decks/paper/front_frame.k",
              ("endtim=0.003",))]
    for label, deck, extra in cases:
        name = os.path.splitext(os.path.basename(deck))[0]
        p0, serial = run_deck(deck, "metis_serial_" + name, extra=extra)
        for n in (2, 4):
            out = os.path.join(TMP, f"metis{n}_{name}")
            p = mpirun(n, ["i=" + os.path.join(ROOT, deck), "outdir=" + out, "decomp=metis", *extra])
            ok, msg = (False, p.stderr[-300:]) if p.returncode or p0.returncode else same_dynamics(serial, out)
            head = ""
            if ok:
                head = next((l for l in open(os.path.join(out, "d3hsp")) if "d o m a i n" in l), "")
                t = domain_table(out)
                costs = [c for c, _, _ in t.values()]
                ok = "METIS k-way" in head and len(t) == n and max(costs) <= 1.05 * sum(costs) / n
                msg = f"{head.strip()} costs {costs}"
            record(f"MPI decomp=metis, {label}: mpirun -np {n} gives the serial run's motion bitwise, its "
                   f"energies to 1e-12, parts within 1.05 of the mean cost", ok, msg + f" rc={p.returncode}")
    p = run([XDYNA, "i=" + os.path.join(ROOT, "input_decks/paper/front_frame.k"), "--check", "parts=2",
             "decomp=graph"])
    record("decomp=graph: an input error naming the value and the choices (exit 1)",
           p.returncode == 1 and "decomp=graph must be rcb or metis" in p.stdout + p.stderr,
           f"rc={p.returncode} {(p.stdout + p.stderr)[-200:]}")


@pytest.mark.slow(88)
def test_mpi_contact_own():
    """Own contact bounds (issue 32, the first step of ghosts by
    proximity; the default, here without the ghosts, XDYNA_GHOSTS=0): each rank bounds the motion of its own contact surface
    nodes alone (the surface's mean velocity an exact fixed-point sum, the
    largest speeds and the margins used maxima, each reduced over the
    ranks), so no rank needs a surface velocity it does not own to decide
    the searches; the decisions are the serial run's, and so is the motion
    bit for bit, energies to 1e-12 (same_dynamics): the tube crush on 2 and
    4 ranks, and dumped on 2 ranks mid-crush (each node's bound gathered
    from its rank) and restarted on 4. The contacts' work is each rank's
    own slaves' pairs', the ranks' sums added (the sliding energy in glstat
    to 1e-12 of its peak, same_dynamics; a restart's sums stay on rank 0:
    left on every rank, the restarted run's sliding energy came out too
    large, checked by hand when this was written)."""
    if mpi_missing():
        return
    env = {"XDYNA_CONTACT_OWN": "1", "XDYNA_GHOSTS": "0"}
    deck = with_cards("input_decks/contact/tube_crush.k", "own_tube", "*DATABASE_BINARY_D3DUMP\n         0\n")
    p0, serial = run_deck(deck, "own_serial", extra=("endtim=0.002",))
    for n in (2, 4):
        out = os.path.join(TMP, f"own{n}")
        p = mpirun(n, ["i=" + deck, "outdir=" + out, "endtim=0.002"], env_extra=env)
        ok, msg = (False, p.stderr[-300:]) if p.returncode or p0.returncode else same_dynamics(serial, out)
        named = ok and "bounds the motion of its own surface nodes alone" in open(os.path.join(out, "d3hsp")).read()
        record(f"XDYNA_CONTACT_OWN: the tube crush on {n} ranks, each bounding its own surface nodes' motion, gives "
               "the serial run's motion bitwise, energies to 1e-12 (named in d3hsp)", ok and named, msg)
    # the contact's arrays d3hsp counts (its surfaces, lists and per-slave
    # records; every rank's whole until they are sized to the rank's
    # slaves): more than nothing and less than the peak the process held,
    # on one rank and on each of 4 (a count that missed the surfaces or
    # counted an array twice over would leave these bounds)
    figs = []
    for run_, pat in ((serial, r" contact arrays at the end \.+ +([0-9.]+) MB"),
                      (os.path.join(TMP, "own4"), r" contact arrays at the end per rank \.\.\. +([0-9.]+) MB \(rank \d+\) to "
                                                  r"+([0-9.]+) MB")):
        txt = open(os.path.join(run_, "d3hsp")).read() if os.path.exists(os.path.join(run_, "d3hsp")) else ""
        c = re.search(pat, txt)
        h = re.search(r"peak memory (?:per rank )?\(VmHWM\) \.+ +([0-9.]+) MB(?: \(rank \d+\) to +([0-9.]+) MB)?", txt)
        if c and h:
            figs.append((float(c.group(c.lastindex)), float(h.group(1))))
    record(f"the contact's arrays counted in d3hsp: (arrays MB, smallest peak MB) {figs}, serial then 4 ranks' "
           "largest", len(figs) == 2 and all(0.0 < a_ < h_ for a_, h_ in figs))
    # the search lists in the rank's own slaves' rows (lists_rows): on 4
    # ranks the largest rank's lists (their per-slave arrays and stores)
    # under 35% of the serial run's. Each rank lists its own slaves, and
    # the run's closing dump, which gathers every slave's lists to every
    # rank, leaves each rank its rows' entries alone (the stores cut to
    # them, where the serial store keeps its room for the searches): 18.8%
    # measured when this was written; 50.0% with every slave's per-slave
    # arrays on every rank and the gathered store kept (before the rows),
    # which this fails.
    lists = []
    for run_ in (serial, os.path.join(TMP, "own4")):
        txt = open(os.path.join(run_, "d3hsp")).read() if os.path.exists(os.path.join(run_, "d3hsp")) else ""
        c = re.search(r"search lists ([0-9.]+)", txt)
        if c:
            lists.append(float(c.group(1)))
    share = lists[1] / lists[0] if len(lists) == 2 and lists[0] > 0 else 1.0
    record(f"the search lists by rows: on 4 ranks the largest rank's search lists are {share:.1%} of the serial "
           f"run's ({lists} MB; under 35%)", len(lists) == 2 and 0.0 < share < 0.35)
    part = os.path.join(TMP, "own_rs")
    p1 = mpirun(2, ["i=" + deck, "outdir=" + part, "endtim=0.0014"], env_extra=env)
    # the dump holds every surface node's motion bound, each from its rank:
    # the serial dump's at the same cycle, bit for bit
    q, sdump = run_deck(deck, "own_serial_dump", extra=("endtim=0.0014",))
    try:
        with h5py.File(os.path.join(sdump, "d3dump.h5"), "r") as fa, \
                h5py.File(os.path.join(part, "d3dump.h5"), "r") as fb:
            keys = [f"contact/i1/{k}" for k in ("node_drift", "class_drift", "class_used")]
            same = all(np.array_equal(fa[k][()], fb[k][()]) for k in keys)
            detail = f"{len(fa[keys[0]])} nodes, largest bound {fa[keys[0]][()].max():.3e}"
    except (OSError, KeyError) as err:
        same, detail = False, str(err)
    record(f"XDYNA_CONTACT_OWN: a 2-rank dump's motion bounds equal the serial dump's bitwise ({detail})",
           same and q.returncode == 0 and p1.returncode == 0, detail)
    p2 = mpirun(4, ["r=" + os.path.join(part, "d3dump.h5"), "endtim=0.002"], env_extra=env) \
        if p1.returncode == 0 else p1
    ok, msg = same_dynamics(serial, part) if p2.returncode == 0 else (False, (p1.stderr + p2.stderr)[-300:])
    record("XDYNA_CONTACT_OWN: the tube crush dumped on 2 ranks at 1.4 ms (in contact since 1.25 ms) "
           "and restarted on 4 gives the serial run's motion bitwise, its sliding energy to 1e-12", ok, msg)
    # the ghosts on top (the default, named here): the surfaces' velocities only to the ranks
    # whose slaves read them, chosen at each search from gathered
    # positions and every rank's box: the tube crush (self-contact) and the
    # front frame (rigid bodies, a rigid wall, two interfaces) on 2 and 4
    # ranks, and the tube restarted across rank counts, the serial motion
    # bitwise; and the two bars of two_bars_penalty.k, each on its own
    # rank, whose every contact is across ranks (with each rank's box
    # shrunk to its slaves alone, the other bar's nodes were not sent and
    # kept their positions of the last search: the bars' run differed from
    # the serial one, checked by hand when this was written).
    # (XDYNA_CHECK_GHOSTS=1: each search's exchange checked against every
    # surface node gathered from its rank, below)
    genv = {"XDYNA_CONTACT_OWN": "1", "XDYNA_GHOSTS": "1", "XDYNA_CHECK_GHOSTS": "1"}
    frame = "input_decks/paper/front_frame.k"
    # (the bars with nodout and rcforc every 1e-6 s, not every cycle: on
    # the cycles between, each contact goes only to its nodes' ranks)
    bars = os.path.join(TMP, "ghost_bars.k")
    with open(os.path.join(ROOT, "input_decks/contact/two_bars_penalty.k")) as fh:
        text = fh.read()
    for db in ("NODOUT", "RCFORC"):
        assert f"*DATABASE_{db}\n 2.000e-07\n" in text
        text = text.replace(f"*DATABASE_{db}\n 2.000e-07\n", f"*DATABASE_{db}\n 1.000e-06\n")
    with open(bars, "w") as fh:
        fh.write(text)
    pf, fserial = run_deck(frame, "ghost_frame_serial", extra=("endtim=0.003",))
    pb, bserial = run_deck(bars, "ghost_bars_serial")
    for label, dk, ref, end in (("tube crush", deck, serial, "endtim=0.002"),
                                ("front frame", os.path.join(ROOT, frame), fserial, "endtim=0.003"),
                                ("two bars (each on its rank: every contact across ranks)", bars,
                                 bserial, "endcyc=1000000000")):
        for n in (2, 4):
            out = os.path.join(TMP, f"ghost{n}_{label.replace(' ', '_')}")
            p = mpirun(n, ["i=" + dk, "outdir=" + out, end], env_extra=genv)
            ok, msg = (False, p.stderr[-300:]) if p.returncode or p0.returncode or pf.returncode or pb.returncode \
                else same_dynamics(ref, out)
            m = re.search(r"contact ghosts \(rank 0\): lists made (\d+) times.*local search gathers (\d+) of its "
                          r"surfaces' (\d+) nodes.*it applied ([0-9.]+)% of the contact pairs",
                          open(os.path.join(out, "d3hsp")).read()) if ok else None
            # between searches the local search gathers only the surface
            # nodes the rank moves (its own, its halo, its ghosts): on 4
            # ranks fewer than the whole surface (had the list missed a
            # node a slave reads, the motion would not be the serial run's);
            # and another rank's slave's pair is applied only where it
            # reaches a node the rank moves: the tube crush's rank 0 on 4
            # ranks applies fewer than all (had one been left out that a
            # node of this rank takes, the motion would differ)
            fewer = m is not None and (n == 2 or int(m.group(2)) < int(m.group(3)))
            fewer = fewer and (n == 2 or label != "tube crush" or float(m.group(4)) < 100)
            # and on a cycle no output reads every pair, each contact found
            # goes only to the ranks that integrate its nodes (an event to
            # every rank): such cycles ran (had a contact missed a rank that
            # integrates one of its segment's nodes, the motion would not be
            # the serial run's: sending it to the slave's rank alone made
            # the tube crush and the front frame on 3 ranks differ, checked
            # by hand when this was written), and on the tube crush on 4
            # ranks a cycle's exchange sent fewer bytes than every contact
            # to every rank did on the output cycles
            x = re.search(r"contacts exchanged between the ranks.*?: (\d+) times each contact found to its nodes' "
                          r"ranks alone, (\d+) bytes sent a time over all ranks; (\d+) times every contact to every "
                          r"rank.*?, (\d+) bytes a time", open(os.path.join(out, "d3hsp")).read()) if ok else None
            sent = x is not None and int(x.group(1)) > 0 and int(x.group(3)) > 0
            sent = sent and (n == 2 or label != "tube crush" or int(x.group(2)) < int(x.group(4)))
            # and at each search a rank holds current exactly what the search
            # reads: its own surface nodes inside another rank's search box
            # go to it, and a ghost's position and velocity come with its
            # number. Every search checked against every surface node from
            # its rank: none held current but not its rank's, no master node
            # inside a rank's search box missing (sending nothing at a search
            # left 47,468 such nodes on the tube crush on 3 ranks, and ghosts
            # named without their positions 1,086 stale ones, while the
            # motion stayed the serial run's on these decks: the ghosts'
            # margins covered what the searches read; checked by hand)
            c = re.search(r"contact ghosts checked \(XDYNA_CHECK_GHOSTS=1\) at (\d+) searches.*?: (\d+) surface nodes "
                          r"checked, (\d+) held current but not their rank's, (\d+) master nodes within a rank's "
                          r"search box not held current", open(os.path.join(out, "d3hsp")).read()) if ok else None
            checked = c is not None and int(c.group(1)) > 0 and int(c.group(2)) > 0 and c.group(3) == "0" \
                and c.group(4) == "0"
            record(f"XDYNA_GHOSTS: the {label} on {n} ranks with contact ghosts by proximity gives the serial run's "
                   f"motion bitwise, energies to 1e-12 ({m.group(1) if m else 0} ghost lists; rank 0's local search "
                   f"gathers {m.group(2) if m else '?'} of {m.group(3) if m else '?'} surface nodes a cycle and it "
                   f"applies {m.group(4) if m else '?'}% of the pairs listed; the contacts sent to their nodes' ranks "
                   f"{x.group(1) if x else '?'} times, {x.group(2) if x else '?'} bytes a time, to every rank "
                   f"{x.group(3) if x else '?'} times, {x.group(4) if x else '?'} bytes a time; checked at "
                   f"{c.group(1) if c else '?'} searches, {c.group(2) if c else '?'} nodes: {c.group(3) if c else '?'} "
                   f"stale, {c.group(4) if c else '?'} missing)",
                   ok and m is not None and int(m.group(1)) > 1 and fewer and sent and checked, msg)
    part = os.path.join(TMP, "ghost_rs")
    p1 = mpirun(2, ["i=" + deck, "outdir=" + part, "endtim=0.0014"], env_extra=genv)
    p2 = mpirun(4, ["r=" + os.path.join(part, "d3dump.h5"), "endtim=0.002"], env_extra=genv) \
        if p1.returncode == 0 else p1
    ok, msg = same_dynamics(serial, part) if p2.returncode == 0 else (False, (p1.stderr + p2.stderr)[-300:])
    record("XDYNA_GHOSTS: the tube crush dumped on 2 ranks at 1.4 ms and restarted on 4 gives the serial run's "
           "motion bitwise", ok, msg)
    # on 8 ranks a rank's own slaves (155 of the tube's 1,240) and the
    # other ranks' slaves the exchange brought are under a quarter of the
    # slaves: the pairs are listed from those alone (pair_candidates, in
    # slave order), on 2 and 4 ranks from a scan of every slave. Had a
    # slave holding a contact or an event been left out of them, its pair
    # would be missing from the nodes' sums and the motion would differ
    # (the listing's order is the sums' order, so a pair out of place
    # would change the bits too): the received slaves left out, this
    # failed (checked by hand when this was written).
    out = os.path.join(TMP, "ghost8_tube")
    p = mpirun(8, ["i=" + deck, "outdir=" + out, "endtim=0.002"], env_extra=genv)
    ok, msg = (False, p.stderr[-300:]) if p.returncode or p0.returncode else same_dynamics(serial, out)
    y = re.search(r"the pairs listed from a rank's own and received slaves alone \(not every slave\) (\d+) times",
                  open(os.path.join(out, "d3hsp")).read()) if ok else None
    record(f"the tube crush on 8 ranks, its pairs listed from each rank's own and received slaves alone "
           f"({y.group(1) if y else '?'} cycles a rank), gives the serial run's motion bitwise, energies to 1e-12",
           ok and y is not None and int(y.group(1)) > 0, msg)


@pytest.mark.slow(20)
def test_mpi_memory_falls():
    """Memory falls with the ranks (issue 32's acceptance): with the nodes
    numbered per rank each rank's nodal arrays hold its own nodes and those
    its elements touch, and its element arrays its own elements, so on 4
    ranks a 100,000-shell plate (NIP 5, plastic, clamped on one edge; 20
    cycles) holds under 40% of the serial run's nodal and element arrays a
    rank (d3hsp's `nodal and element arrays`: every nodal array, the time
    loop's, the energies' tables, the decomposition's lists and every
    element array a rank holds). A quarter is the floor; the rest is the
    halo and the arrays still held for every element (their connectivity,
    ids and flags; the shells' energies, thickness and area are held by
    row: 30% measured when they were cut, 34% before). The motion stays the serial run's bit for
    bit and the energies to rounding (same_dynamics, 2e-11: sums of 1e5
    terms), and the d3plot states,
    which rank 0 writes from every node gathered, are the serial run's
    bytes. Without the per-rank numbering (XDYNA_LOCAL_NODES=0, the nodes
    whole on every rank) the same run holds 56% (measured when this was
    written), which this test would fail."""
    if mpi_missing():
        return
    d = os.path.join(TMP, "memory_falls")
    os.makedirs(d, exist_ok=True)
    deck = os.path.join(d, "plate.k")
    gen_deck("--bench-shells", "400", "250", deck, "--cycles", "20", "--states-dt", "2.0e-6")
    serial, four = os.path.join(d, "serial"), os.path.join(d, "r4")
    p1 = run([XDYNA, "i=" + deck, "outdir=" + serial])
    p4 = mpirun(4, ["i=" + deck, "outdir=" + four])
    if p1.returncode or p4.returncode:
        record("the 100,000-shell plate runs serial and on 4 ranks", False, (p1.stderr + p4.stderr)[-300:])
        return
    l1 = open(os.path.join(serial, "d3hsp")).read()
    l4 = open(os.path.join(four, "d3hsp")).read()
    n1 = re.search(r"nodal and element arrays \.+ +([0-9.]+) MB", l1)
    n4 = re.search(r"nodal and element arrays per rank \.\.\. +([0-9.]+) MB \(rank \d+\) to +([0-9.]+) MB", l4)
    m = re.search(r"nodes numbered per rank: .*\(rank 0: (\d+) of (\d+)\)", l4)
    share = float(n4.group(2)) / float(n1.group(1)) if n1 and n4 else 1.0
    record(f"memory falls with the ranks: on 4 ranks the 100,000-shell plate holds {share:.1%} of the serial run's "
           f"nodal and element arrays a rank at most ({n4.group(1) if n4 else '?'}-{n4.group(2) if n4 else '?'} MB "
           f"against {n1.group(1) if n1 else '?'} MB; rank 0 numbers {m.group(1) if m else '?'} of "
           f"{m.group(2) if m else '?'} nodes; issue 32 asks under 40%)",
           n1 is not None and n4 is not None and m is not None and share < 0.40 and float(n4.group(1)) > 0)
    # d3hsp's floor under the peak: the process before the deck is read
    # (libraries, Open MPI's buffers), on every rank below its peak by at
    # least the deck's own arrays, which every rank reads after it (a floor
    # taken after the deck, or a rank's value put in another's place, would
    # leave no room for them)
    floors = []
    for txt in (l1, l4):
        fl = re.search(r"of it, the process before the deck +([0-9.]+) MB(?: \(rank \d+\) to +([0-9.]+) MB)?", txt)
        pk = re.search(r"peak memory (?:per rank )?\(VmHWM\) \.+ +([0-9.]+) MB", txt)
        dk = re.search(r"the deck's node and element arrays[ .a-z]* +([0-9.]+) MB", txt)
        if fl and pk and dk:
            floors.append((float(fl.group(fl.lastindex)), float(dk.group(1)), float(pk.group(1))))
    record(f"d3hsp's floor under the peak, serial then 4 ranks (the process before the deck, the deck's arrays, the "
           f"smallest peak, MB): {floors}", len(floors) == 2 and all(0 < f_ and f_ + d_ < p_ for f_, d_, p_ in floors))
    # (the energies, momenta and mean velocities are sums over 100,000
    # nodes and shells, most terms of one sign, grouped by rank: another
    # grouping of N terms may differ by up to N eps of the sum, 1.1e-11 for
    # N = 1e5, where the 1,200-shell plates of test_mpi_owned stay under
    # 1e-12; measured when this was written: 2.7e-12 of the mean velocity,
    # the same with the nodes whole on every rank)
    ok, msg = same_dynamics(serial, four, rtol=2e-11)
    # (the binary family; d3plot.h5 carries the energies too, which agree
    # to rounding, as above)
    fam = sorted(f for f in os.listdir(serial) if f.startswith("d3plot") and not f.endswith(".h5"))
    differ = [f for f in fam if not os.path.exists(os.path.join(four, f)) or
              open(os.path.join(serial, f), "rb").read() != open(os.path.join(four, f), "rb").read()]
    states = len(fam) > 1 and not differ
    if differ:
        msg = f"{msg}; d3plot files that differ: {differ} of {len(fam)}"
    record("the plate with its nodes numbered per rank: the serial motion bitwise, the energies to 2e-11 (the sums' "
           "rounding over 1e5 terms), the d3plot family's bytes the serial run's", ok and states, msg)


@pytest.mark.slow(10)
def test_mpi_initial_penetrations():
    """Initial penetrations searched by the ranks together (issue 32): each
    rank runs the search on its block of each interface's slaves and the
    ranks agree on each pass's moves (a node's deepest penetration, the
    lowest interface where two are as deep, its direction and place, each
    from one rank). Two 9 x 9 plates of 1 mm shells (contact thickness 1
    mm) start 0.5 mm apart, offset 0.3 mm in plane, so all 162 nodes of
    both lie in the other plate's contact zone, spread over every rank's
    block: under IGNORE 0 each node moves out (half its depth where the
    segment's nodes move the other way, in several passes), under IGNORE 2
    each is named with its way out. On 2 and 3 ranks d3hsp's lines (each
    node, its segment, depth and both coordinates, in the serial order) are
    the serial run's, character for character: a move or a name taken on
    the wrong rank, twice or not at all would change a line or the count;
    and so is the motion that starts from the moved nodes (same_dynamics:
    bitwise, energies to 1e-12)."""
    if mpi_missing():
        return
    n = 9
    for ig in (0, 2):
        lines = ["*KEYWORD", "*TITLE", "two plates overlapping at the start", "*CONTROL_TERMINATION", "  2.0e-5",
                 "*CONTROL_TIMESTEP", "         0       0.9", "*DATABASE_GLSTAT", "  1.0e-7", "*DATABASE_NODOUT",
                 "  1.0e-7", "*CONTROL_CONTACT", "0.1", "", "", f"{ig:10d}",
                 "*SECTION_SHELL", "         1         2         1         3", "     0.001     0.001     0.001     0.001",
                 "*MAT_ELASTIC", "         1      7850 2.000e+11       0.3",
                 "*PART", "held", "         1         1         1", "*PART", "upper", "         2         1         1",
                 "*NODE"]
        held, held_e = shell_grid(n, 1, 1, 0)
        upper, upper_e = shell_grid(n, 1001, 2, len(held_e), shift=0.3e-3, z=0.5e-3)
        lines += held + upper + ["*ELEMENT_SHELL"] + held_e + upper_e + node_set(1, list(range(1, 1 + n * n)))
        lines += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         1         1         1",
                  "*INITIAL_VELOCITY_NODE", "      1041         0         0      -2.0",
                  "*DATABASE_HISTORY_NODE", "      1041      1001",
                  "*CONTACT_AUTOMATIC_SINGLE_SURFACE", "         0", "0.0", "0.0", "*END"]
        deck = write_lines(os.path.join(TMP, f"overlap_ig{ig}.k"), lines)
        p0, serial = run_deck(deck, f"overlap_ig{ig}_serial")

        def named(out):
            txt = open(os.path.join(out, "d3hsp")).read() if os.path.exists(os.path.join(out, "d3hsp")) else ""
            return [ln for ln in txt.splitlines() if "initially inside" in ln or "initial penetrations" in ln
                    or "slave nodes moved" in ln]
        ref = named(serial)
        what = "moved out (IGNORE 0)" if ig == 0 else "(IGNORE 2, tracked)"
        count = sum(what in ln for ln in ref)
        for nr in (2, 3):
            out = os.path.join(TMP, f"overlap_ig{ig}_r{nr}")
            p = mpirun(nr, ["i=" + deck, "outdir=" + out])
            ok, msg = (False, (p0.stderr + p.stderr)[-300:]) if p.returncode or p0.returncode \
                else same_dynamics(serial, out)
            got = named(out)
            record(f"initial penetrations on {nr} ranks, IGNORE {ig}: {count} of 162 nodes {what}, d3hsp's "
                   f"{len(got)} lines the serial run's {len(ref)} in order, the motion from them the serial run's",
                   ok and count == 162 and got == ref, msg)


@pytest.mark.slow(30)
def test_mpi_local_decks():
    """Nodes numbered per rank on the verification decks without contact
    (issue 32): bars and blocks of hexahedra against rigid walls (a moving
    heavy one among them) and a pole, a block dropped under gravity (a
    body load), a prestressed block, a Taylor bar, a spinning free block,
    shells in bending, warped and spinning, and triangles in tension. On 3
    ranks each rank holds its own nodes and those its elements touch
    (d3hsp says so), and the motion is the serial run's bit for bit, the
    energies to rounding (same_dynamics: 1e-12 of their scale). A wrong
    renumbering (a list left in the model's numbers) moves a node or
    fails the run."""
    if mpi_missing():
        return
    for name in ("bar_heavy_wall", "bar_on_pole", "gravity_drop", "prestressed_block", "taylor_bar_coarse",
                 "free_block_spin", "shell_cantilever", "shell_warped_spin", "shell_tension_tri"):
        deck = os.path.join(ROOT, "input_decks", "verify", name + ".k")
        serial, three = os.path.join(TMP, "local_" + name + "_1"), os.path.join(TMP, "local_" + name + "_3")
        p1 = run([XDYNA, "i=" + deck, "outdir=" + serial])
        p3 = mpirun(3, ["i=" + deck, "outdir=" + three])
        if p1.returncode or p3.returncode:
            record(f"nodes numbered per rank, {name}: serial and 3 ranks run", False, (p1.stderr + p3.stderr)[-300:])
            continue
        ok, msg = same_dynamics(serial, three)
        local = "nodes numbered per rank" in open(os.path.join(three, "d3hsp")).read()
        record(f"nodes numbered per rank, {name}: 3 ranks give the serial motion bitwise, the energies to 1e-12",
               ok and local, msg if local else "d3hsp: not numbered per rank")


@pytest.mark.slow(26)
def test_mpi_cards_in_blocks():
    """Under MPI each rank reads its block of a large *NODE and
    *ELEMENT_SHELL keyword's cards and every card's record goes to all
    (xd_input_read_geometry's read_in_blocks, from 1,000 cards a rank): a
    60 x 60 shell plate with whole-model contact (3,721 nodes, 3,600
    shells: blocks of 1,860 and 1,800 cards on 2 ranks) runs on 2 ranks as
    on one (ranks_match: the motion bitwise). A bad card in the second
    rank's block stops both runs with exit 1 and the same message naming
    its file, line, keyword and field (every rank reads the cards again in
    order once some rank found an error): a node's X and a shell's node
    id. Exact: no tolerance."""
    if mpi_missing():
        return
    d = os.path.join(TMP, "cards_in_blocks")
    os.makedirs(d, exist_ok=True)
    deck = os.path.join(d, "plate.k")
    gen_deck("--bench-shells", "60", "60", deck, "--cycles", "30", "--contact")
    text = open(deck).read()
    serial = os.path.join(d, "one")
    p = run([XDYNA, "i=" + deck, "outdir=" + serial])
    ok, msg = two_ranks_match(deck, serial) if p.returncode == 0 else (False, p.stderr[-300:])
    record(f"cards read in blocks by 2 ranks: the 60 x 60 plate's run is the serial one's ({msg})", ok, msg)
    lines = text.split("\n")
    node0 = lines.index("*NODE")
    shell0 = lines.index("*ELEMENT_SHELL")
    # (the bad text in its field's columns: a node's X in 9-24, a shell's
    # N1 in 17-24)
    for what, k, a, new in (("a node's X", node0 + 3000, 8, f"{'1.2.3':>16s}"),
                            ("a shell's node id", shell0 + 3000, 16, f"{'0':>8s}")):
        bad = list(lines)
        bad[k] = bad[k][:a] + new + bad[k][24:]
        path = os.path.join(d, "bad.k")
        write_lines(path, bad)
        one = run([XDYNA, "i=" + path, "outdir=" + os.path.join(d, "bad1")])
        two = mpirun(2, ["i=" + path, "outdir=" + os.path.join(d, "bad2")])
        e1 = [ln for ln in one.stderr.splitlines() if "bad.k:" in ln]
        e2 = [ln for ln in two.stderr.splitlines() if "bad.k:" in ln]
        ok = (one.returncode == 1 and two.returncode == 1 and len(e1) > 0 and len(e2) > 0 and e2[0] == e1[0]
              and f"bad.k:{k + 1}:" in e1[0])
        record(f"a bad card in the second rank's block ({what}, line {k + 1}): exit 1 on 1 and 2 ranks, the same "
               f"message ({e1[0] if e1 else '?'})", ok, one.stderr[-300:] + two.stderr[-300:])


def test_mpi_owned():
    """Owned nodes (issue 32, deliverable 1): where a model has none of the
    features that still need every node on every rank (contact, walls,
    rigid bodies, ties, beams, loads, erosion, mass scaling), each rank
    integrates only the nodes it assembles, sends its halo's force slots to
    their nodes' ranks alone and, after each step, its nodes' motion to the
    ranks whose elements touch them, point-to-point; every node is gathered
    only for the states and dumps (the nodout nodes for the histories). The
    force on a node is still the sum of its slots in the serial order, and
    every value that crosses has one sender, so the motion is the serial
    run's bit for bit: a plastic
    shell plate (NIP 5, states, nodout with rotations on nodes on both
    sides of the cuts, written every cycle) and a hexahedral block, 2 and 4
    ranks, one and two threads, a restart across rank counts. The energies,
    momenta and mean velocities are each rank's sums added over the ranks,
    so those agree to rounding (same_dynamics), the rest bit for bit. (A run
    whose halo motion was left out differs from the serial one at the
    first energy row: checked by hand when this was written, 17 of 20
    series, at 1e-6 and more.)"""
    if mpi_missing():
        return
    d = os.path.join(TMP, "owned")
    os.makedirs(d, exist_ok=True)
    plate, hexes = os.path.join(d, "plate.k"), os.path.join(d, "hex.k")
    gen_deck("--bench-shells", "40", "30", plate, "--cycles", "200", "--states-dt", "2e-5")
    gen_deck("--bench", "20", "10", "6", hexes, "--cycles", "200")
    text = open(plate).read().replace("*KEYWORD\n", "*KEYWORD\n*DATABASE_BINARY_D3DUMP\n         0\n"
                                      "*DATABASE_NODOUT\n1.0e-6\n*DATABASE_HISTORY_NODE\n1,21,641,660,1271\n", 1)
    with open(plate, "w") as fh:
        fh.write(text)
    # the plate again under a moving rigid wall 2 mm above it (NSID 0: every
    # node; mass 2 kg) and a prescribed velocity on its far edge (nodes
    # 1231-1271, across the cuts) ramped from 30 m/s to 0: the wall's
    # mass, impulse, force and energy are sums over nodes of every rank,
    # taken in the serial order (the motion reads them); the prescribed
    # work is each rank's nodes' sum added over the ranks, as the other
    # energies (to 1e-12: same_dynamics)
    walled = os.path.join(d, "walled.k")
    edge = "\n".join("".join(f"{n:10d}" for n in range(a, min(a + 8, 1272))) for a in range(1231, 1272, 8))
    with open(walled, "w") as fh:
        fh.write(text.replace("*NODE\n", "*SET_NODE_LIST\n         2\n" + edge + "\n*DEFINE_CURVE\n         7\n"
                              " 0.0, 30.0\n 1.0e-4, 0.0\n 1.0, 0.0\n*BOUNDARY_PRESCRIBED_MOTION_SET\n"
                              "         2         3         0         7       1.0\n*RIGIDWALL_PLANAR_MOVING\n"
                              "         0\n0.0,0.0,0.002,0.0,0.0,0.0,0.0\n2.0,0.0\n*DATABASE_RWFORC\n1.0e-6\n"
                              "*NODE\n", 1))
    # the plate under a body load (1,000 g along z) and a pressure on the
    # row of shells across the middle (40 segments across the cuts): every
    # rank takes every segment's force, and the power of both is each
    # rank's nodes' sum added over the ranks
    loaded = os.path.join(d, "loaded.k")
    segs = "".join(f"         9       1.0       0.0{a:10d}{a + 1:10d}{a + 42:10d}{a + 41:10d}\n*LOAD_SEGMENT\n"
                   for a in (15 * 41 + i + 1 for i in range(40)))
    with open(loaded, "w") as fh:
        fh.write(text.replace("*NODE\n", "*DEFINE_CURVE\n         8\n 0.0, 9810.0\n 1.0, 9810.0\n*DEFINE_CURVE\n"
                              "         9\n 0.0, 1.0e5\n 1.0, 1.0e5\n*LOAD_BODY_Z\n         8       1.0\n"
                              "*LOAD_SEGMENT\n" + segs[:-len("*LOAD_SEGMENT\n")] + "*NODE\n", 1))
    for label, deck in (("plastic shell plate, NIP 5, nodout with rotations", plate),
                        ("hexahedral block", hexes),
                        ("plate under a moving rigid wall with a prescribed edge", walled),
                        ("plate under a body load and a pressure across the cuts", loaded),
                        ("spot-welded plates (beams on both ranks)", os.path.join(ROOT, "input_decks/verify/spot_weld.k"))):
        serial = os.path.join(d, "serial_" + os.path.basename(deck)[:-2])
        p0 = run([XDYNA, "i=" + deck, "outdir=" + serial])
        for n, threads in ((2, 1), (4, 1), (2, 2)):
            if deck.endswith("spot_weld.k") and n == 4:
                continue
            out = os.path.join(d, f"r{n}t{threads}_" + os.path.basename(deck)[:-2])
            p = mpirun(n, ["i=" + deck, "outdir=" + out], threads=threads)
            if p.returncode or p0.returncode:
                record(f"owned nodes, {label}: {n} ranks x {threads} threads run", False, p.stderr[-300:])
                continue
            ok, msg = same_dynamics(serial, out)
            log = open(os.path.join(out, "d3hsp")).read()
            m = re.search(r"owned nodes: each rank integrates the nodes it assembles \(rank 0: (\d+) of (\d+)\)", log)
            # rank 0 integrates a share of the nodes, not all: at most its
            # elements' share plus a fifth of the model (the nodes on the
            # cuts go to the lower rank, and the block's 1,200 solids are
            # split in groups of 128: 0.61 of its nodes on 2 ranks)
            share = int(m.group(1)) / int(m.group(2)) if m else 1.0
            states = True
            for f in ("d3plot", "d3plot01"):
                a, b = os.path.join(serial, f), os.path.join(out, f)
                if os.path.exists(a):
                    states = states and os.path.exists(b) and open(a, "rb").read() == open(b, "rb").read()
            # the nodes numbered per rank where nothing reads every node
            # (the plate, the block, the wall with the prescribed edge);
            # the pressure segments and the spot welds' rigid bodies keep
            # them whole, named
            want = {"loaded.k": "every node on every rank, for pressure loads",
                    "spot_weld.k": "every node on every rank, for rigid bodies"}.get(os.path.basename(deck),
                                                                          "nodes numbered per rank")
            record(f"owned nodes, {label}: {n} ranks x {threads} threads give the serial motion and states "
                   f"bitwise, the energies to 1e-12; rank 0 integrates {share:.2f} of the nodes; d3hsp: '{want}'",
                   ok and states and m is not None and share <= 1.0 / n + 0.2 and want in log, msg)
    # the elements' state and force slots (the shells' points' stresses,
    # plastic strains and hourglass forces, NIP 5, and their force and
    # moment slots: 472 bytes a shell; the solids' stresses, volumes,
    # hourglass forces and force slots: 352 bytes a hexahedron) are held by
    # each rank for its own elements alone, with its halo's slots (issue
    # 32): on 4 ranks each holds about a quarter of the serial run's (the
    # plate's 1,200 shells cut in 300s by the bisection, the halo's slots
    # under 1% of the whole; the block's 1,200 hexahedra in groups of 128,
    # so a rank may hold a group more than its quarter, and a block this
    # small has a large halo: its cut faces' slots, 6% of the whole on rank
    # 0, are allowed up to a tenth), and the figure for all elements it
    # gives is the serial run's, exactly
    for tag, spare in (("plate", 0.02), ("hex", 128 / 1200 + 0.1)):
        logs = {}
        for run_ in ("serial_" + tag, "r4t1_" + tag):
            path = os.path.join(d, run_, "d3hsp")
            logs[run_] = open(path).read() if os.path.exists(path) else ""
        m1 = re.search(r"elements' state and force slots \(stresses, strains, hourglass and nodal forces\) \.+ +"
                       r"([0-9.]+) MB",
                       logs["serial_" + tag])
        m4 = re.search(r"elements' state and force slots per rank \.\.\. +([0-9.]+) MB \(rank \d+\) to +([0-9.]+) MB "
                       r"\(rank \d+\), each rank its own elements' and its halo's slots \(all elements': +([0-9.]+) MB\)",
                       logs["r4t1_" + tag])
        ok = m1 is not None and m4 is not None
        if ok:
            one, lo, hi, every = (float(x) for x in (m1.group(1), m4.group(1), m4.group(2), m4.group(3)))
            ok = one > 0 and 0 < lo and hi <= (0.25 + spare) * one and abs(every - one) <= 1e-3 * one
        record(f"owned nodes, {tag}: the elements' state and slots on 4 ranks, each rank at most {0.25 + spare:.2f} of the "
               f"serial run's, all of it the serial run's ({m4.group(0) if m4 else 'no line'}; serial "
               f"{m1.group(1) if m1 else '?'} MB)", ok)
        # every nodal and element array a rank holds (d3hsp's measure for
        # issue 32's memory test): on 4 ranks each rank holds less than the
        # serial run by at least three quarters of the state and slots it
        # no longer holds (on a model this small the halo and the arrays
        # still held per element of the model weigh more than on a large
        # one: test_mpi_memory_falls holds a 1e5-shell plate to the
        # issue's 40%)
        n1 = re.search(r"nodal and element arrays \.+ +([0-9.]+) MB", logs["serial_" + tag])
        n4 = re.search(r"nodal and element arrays per rank \.\.\. +([0-9.]+) MB \(rank \d+\) to +([0-9.]+) MB",
                       logs["r4t1_" + tag])
        ok = ok and n1 is not None and n4 is not None
        if ok:
            whole, hi4 = float(n1.group(1)), float(n4.group(2))
            ok = hi4 <= whole - 0.75 * (one - hi)
        record(f"owned nodes, {tag}: every nodal and element array on 4 ranks, at most "
               f"{n4.group(2) if n4 else '?'} MB a rank against the serial run's {n1.group(1) if n1 else '?'} MB "
               f"({(float(n4.group(2)) / float(n1.group(1)) if n1 and n4 else 0):.0%}; issue 32 asks under 40%), "
               f"less by at least three quarters of the state and slots a rank gave up", ok)
    # the deck's own node and element arrays (every rank holds them whole,
    # d3hsp names them apart): cut to their counts once the deck is read,
    # not the room they grew into by doubling, and the cards' source lines
    # released once the model check has read them, and what only the
    # set-up reads released once it is done (the nodes' two constraint
    # codes, the shells' four nodal thicknesses, of which their mean stays):
    # the plate's 1,271 nodes at 28 bytes (id, coordinates) and 1,200
    # shells at 36 (id, part as read and checked, connectivity, mean
    # thickness), to the 1e-4 MB d3hsp prints (the doubled room, 2,048
    # of each, would be 0.2 MB; with the source lines, 0.1217 MB; with the
    # set-up's arrays, 0.1123 MB)
    want = (1271 * 28 + 1200 * 36) / 1048576.0
    got = []
    for run_ in ("serial_plate", "r4t1_plate"):
        path = os.path.join(d, run_, "d3hsp")
        txt = open(path).read() if os.path.exists(path) else ""
        for line in txt.splitlines():
            if line.startswith(" the deck's node and element arrays"):
                got += [float(x) for x in re.findall(r"([0-9.]+) MB", line)]
    record(f"the deck's node and element arrays held at their counts: {got} MB against {want:.4f} (serial, then "
           "4 ranks' smallest and largest)",
           len(got) == 3 and all(abs(g - want) <= 1.5e-4 for g in got))
    with h5py.File(os.path.join(d, "serial_walled", "thist.h5"), "r") as f:
        wall_e, ext = f["glstat/stonewall_energy"][-1], f["glstat/external_work"][-1]
        ke0 = f["glstat/kinetic_energy"][0]
    # (both act: the wall takes energy and the edge's deceleration does
    # negative work, each at least a percent of the initial kinetic energy)
    record(f"owned nodes: the wall and the prescribed edge act (wall energy {wall_e:.4g} J, external work "
           f"{ext:.4g} J, initial kinetic energy {ke0:.4g} J)", wall_e > 0.01 * ke0 and ext < -0.01 * ke0)
    with h5py.File(os.path.join(d, "serial_loaded", "thist.h5"), "r") as f:
        ext = f["glstat/external_work"][-1]
    # (the loads' work: at least a percent of the initial kinetic energy)
    record(f"owned nodes: the body load and the pressure do work ({ext:.4g} J against {ke0:.4g} J initial kinetic "
           "energy)", abs(ext) > 0.01 * ke0)
    # a restart across rank counts: dumped on 2 ranks at cycle 100 (every
    # node gathered for the dump), restarted on 4 to the end
    full = os.path.join(d, "serial_plate")
    part = os.path.join(d, "rs_plate")
    p1 = mpirun(2, ["i=" + plate, "outdir=" + part, "endcyc=100"])
    p2 = mpirun(4, ["r=" + os.path.join(part, "d3dump.h5")]) if p1.returncode == 0 else p1
    ok, msg = same_dynamics(full, part) if p2.returncode == 0 else (False, (p1.stderr + p2.stderr)[-300:])
    record("owned nodes: dumped on 2 ranks at cycle 100, restarted on 4, the serial run's motion bitwise (nodout "
           "rotations included)", ok, msg)
    # the replicated state on request, and where a feature needs it, named
    out = os.path.join(d, "replicated")
    p = mpirun(2, ["i=" + hexes, "outdir=" + out], env_extra={"XDYNA_REPLICATED": "1"})
    ok, msg = same_histories(os.path.join(d, "serial_hex"), out) if p.returncode == 0 else (False, p.stderr[-300:])
    log = open(os.path.join(out, "d3hsp")).read() if p.returncode == 0 else ""
    record("owned nodes: XDYNA_REPLICATED=1 keeps every node on every rank, named in d3hsp, the same histories",
           ok and "nodal state: replicated (XDYNA_REPLICATED set): every rank integrates every node" in log, msg)
    # the tube crush (self-contact) and the front frame (rigid bodies, a
    # rigid wall, contact) run with owned nodes: the contact surfaces'
    # velocities and the rigid bodies' nodes' forces to every rank (bitwise
    # motion on 1, 2, 4 ranks and 2 x 2: test_mpi); erosion keeps the
    # replicated state (test_erosion)
    # (the surfaces' velocities to every rank where contact ghosts are off,
    # XDYNA_GHOSTS=0; by default the ghosts replace them: below)
    log = {}
    for name, deck in (("tube", "input_decks/contact/tube_crush.k"), ("frame", "input_decks/paper/front_frame.k")):
        out = os.path.join(d, name)
        p = mpirun(2, ["i=" + os.path.join(ROOT, deck), "outdir=" + out, "endcyc=2"], env_extra={"XDYNA_GHOSTS": "0"})
        log[name] = open(os.path.join(out, "d3hsp")).read() if p.returncode == 0 else ""
    pat = r"the contact surfaces' (\d+) nodes' velocities and the rigid bodies' (\d+) nodes' forces to every rank"
    m = re.search(pat, log["tube"])
    record(f"owned nodes: the tube crush's contact runs with owned nodes ({m.group(1) if m else 0} surface nodes' "
           "velocities to every rank)", m is not None and int(m.group(1)) > 0)
    m = re.search(pat, log["frame"])
    record(f"owned nodes: the front frame's rigid bodies and contact run with owned nodes ({m.group(2) if m else 0} "
           "body nodes' forces to every rank)", m is not None and int(m.group(2)) > 0)
    # the default: contact ghosts by proximity (test_mpi_contact_own holds
    # them to the serial run), named in d3hsp
    out = os.path.join(d, "tube_default")
    p = mpirun(2, ["i=" + os.path.join(ROOT, "input_decks/contact/tube_crush.k"), "outdir=" + out, "endcyc=2"])
    log = open(os.path.join(out, "d3hsp")).read() if p.returncode == 0 else ""
    record("owned nodes: by default the tube crush on 2 ranks takes contact ghosts by proximity and bounds each "
           "rank's own surface nodes' motion, both named in d3hsp",
           "contact: ghosts by proximity (XDYNA_GHOSTS=0: none)" in log
           and "contact: each rank bounds the motion of its own surface nodes" in log, p.stderr[-300:])


def test_part_sizes():
    """What each rank would hold with its own nodes and a halo (issue 32,
    `--check parts=N`), on a plate whose answer is counted by hand: 40 x 40
    shells of 2 mm, 41 x 41 nodes, cut by coordinate bisection into four
    quadrants of 20 x 20 shells. Each quadrant touches 21 x 21 = 441 nodes.
    The halo, summed over the ranks, counts each node once for each rank
    beyond its assembler that touches it: the 80 nodes of the cross but the
    centre, touched by two ranks, and the centre, by four: 80 + 3 = 83. A
    rank exchanges with the assembler of each node it touches and with
    each rank touching a node it assembles: the four pairs across the cuts
    and the diagonal pair through the centre's assembler (the other
    diagonal pair shares nothing else): 2 or 3 a rank, 10 in all. With
    single-surface contact each rank's ghosts are the other ranks'
    segments within the pool margin and the reach of its box (1.41 mm, half
    the 2.83 mm diagonal, + 1 mm: past one shell's width of 2 mm, short of
    two): two rows along each of its two cuts and the diagonal's 2 x 2
    corner (40 + 40 + 4 = 84); their nodes beyond the cuts, two rows of 21
    along each and the corner's four (42 + 42 + 4 = 88). The halo's bytes a cycle: each halo node's
    force and moment out and its motion back, 2 x 8 x 6 bytes a node.
    Exact counts: no tolerance."""
    here = os.path.join(TMP, "part_sizes")
    os.makedirs(here, exist_ok=True)
    n = 41
    nodes, elems = shell_grid(n, 1, 1, 0)
    lines = ["*KEYWORD", "*TITLE", "plate for the partition's sizes", "*CONTROL_TERMINATION", "  1.0e-5",
             "*SECTION_SHELL", "         1         2         1         2", "     0.001     0.001     0.001     0.001",
             "*MAT_ELASTIC", "         1      7850 2.000e+11       0.3", "*PART", "plate", "         1         1         1",
             "*CONTACT_AUTOMATIC_SINGLE_SURFACE", "         0", "0.0", "0.0", "*NODE"] + nodes + ["*ELEMENT_SHELL"] + elems
    lines.append("*END")
    deck = write_lines(os.path.join(here, "plate.k"), lines)
    p = run([XDYNA, "--check", "i=" + deck, "parts=4"], cwd=here)
    rows = re.findall(r"^\s+(\d)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+([0-9.]+)\s+(\d+)$", p.stdout,
                      re.M)
    m = re.search(r"halo nodes over all ranks (\d+)", p.stdout)
    ok = p.returncode == 0 and len(rows) == 4 and m is not None
    got = ""
    if ok:
        v = [[int(x) for x in r[:8]] for r in rows]
        got = (f"shells {[r[2] for r in v]}, nodes {[r[3] for r in v]}, halo {int(m.group(1))}, neighbours "
               f"{[r[5] for r in v]}, ghost segments {[r[6] for r in v]}, ghost nodes {[r[7] for r in v]}")
        hb = [int(r[9]) for r in rows]
        got += f", halo bytes {hb}"
        ok = (all(r[1] == 0 and r[2] == 400 and r[3] == 441 and r[5] in (2, 3) and r[6] == 84 and r[7] == 88
                  for r in v) and int(m.group(1)) == 83 and sum(r[5] for r in v) == 10
              and all(b == 2 * 8 * 6 * r[4] for b, r in zip(hb, v)))
    record(f"--check parts=4: a 40 x 40 plate's quadrants hold 400 shells and 441 nodes each, the halo 83 nodes, "
           f"10 neighbour links, 84 ghost segments and 88 ghost nodes each ({got})", ok, p.stdout[-900:] + p.stderr[-300:])
    # the same plate run on 4 ranks with owned nodes: the bytes a cycle
    # d3hsp gives, from the neighbour lists, against the decomposition's
    # counts above: point-to-point, every halo slot's force and moment
    # (6 x 8 bytes), each node's velocity (3 x 8 bytes) to each other rank
    # (every node is a contact surface node, all 1,681), and the angular
    # velocity (3 x 8 bytes) of the 83 halo node-sends alone (the contact
    # reads no angular velocity); nothing is gathered (no beams, no ties)
    if shutil.which("mpirun") is not None:
        out = os.path.join(here, "owned4")
        q = mpirun(4, ["i=" + deck, "outdir=" + out, "endcyc=2"], env_extra={"XDYNA_GHOSTS": "0"})
        log = open(os.path.join(out, "d3hsp")).read() if q.returncode == 0 else ""
        ms = re.search(r"halo exchange a cycle: (\d+) force slots", log)
        mb = re.search(r"exchange a cycle, all ranks: (\d+) bytes point-to-point \(halo slots and velocities, "
                       r"with the contact surfaces' and pressure segments' to every other rank\), (\d+) bytes of beam",
                       log)
        want = (48 * int(ms.group(1)) + 24 * 3 * n * n + 24 * 83, 0) if ms else None
        gotb = (int(mb.group(1)), int(mb.group(2))) if mb else None
        record(f"owned nodes on the quadrants: bytes a cycle {gotb} against the decomposition's {want} (halo slots "
               f"{ms.group(1) if ms else '?'}, 83 halo nodes, {n * n} surface nodes)", gotb is not None and gotb == want,
               q.stderr[-300:])
        # with contact ghosts (the default) the surfaces' velocities no
        # longer go to every rank: a cycle's bytes are the halo's alone,
        # each halo slot's force and moment and each of the 83 halo
        # node-sends' velocity and angular velocity, proportional to the
        # partition surfaces (the ghosts' own, chosen at each search, are
        # counted at the end of the run)
        out = os.path.join(here, "ghosts4")
        q = mpirun(4, ["i=" + deck, "outdir=" + out, "endcyc=2"])
        log = open(os.path.join(out, "d3hsp")).read() if q.returncode == 0 else ""
        # the run's table, each rank's row made by that rank and summed over
        # the ranks, is the one --check parts=4 makes alone, row for row
        run_rows = re.findall(r"^\s+(\d)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+([0-9.]+)\s+(\d+)$",
                              log, re.M)
        record(f"the 4-rank run's table of what each rank holds (each rank's own row) is --check parts=4's "
               f"({len(run_rows)} rows)", len(rows) == 4 and run_rows == rows, log[-600:] + q.stderr[-300:])
        ms = re.search(r"halo exchange a cycle: (\d+) force slots", log)
        mb = re.search(r"exchange a cycle, all ranks: (\d+) bytes point-to-point \(halo slots and velocities, "
                       r"with the pressure segments' to every other rank; the contact ghosts' come on top", log)
        want = 48 * int(ms.group(1)) + 48 * 83 if ms else None
        gotb = int(mb.group(1)) if mb else None
        record(f"contact ghosts on the quadrants: bytes a cycle {gotb} against the halo's alone {want} (halo slots "
               f"{ms.group(1) if ms else '?'}, 83 halo node-sends)", gotb is not None and gotb == want, q.stderr[-300:])


def test_stack_limit():
    """No set-up temporary the size of the model on the stack (the release
    build puts automatic arrays and array temporaries there,
    -fstack-arrays). The decomposition's coordinates of a set of elements,
    24 MB at 1e6 shells, overflowed the default 8 MB stack of every rank: a
    1,009,200-shell tubes array on 2 ranks died with SIGSEGV before its first
    cycle. Here the 120,000-shell array (2.9 MB of centroids) runs 2 cycles
    with a 1 MB stack on one thread, two threads and 2 ranks: a temporary of
    the model's nodes or elements would not fit (the build before the
    change died on 2 ranks so), while the fixed per-thread work arrays do."""
    deck = os.path.join(TMP, "stack_tubes.k")
    g = gen_deck("--bench-tubes", "10", "10", deck, "--cycles", "2")
    if g.returncode:
        record("stack limit: the 10 x 10 tubes deck is generated", False, g.stderr[-300:])
        return

    def one_mb():
        resource.setrlimit(resource.RLIMIT_STACK, (1 << 20, resource.getrlimit(resource.RLIMIT_STACK)[1]))

    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    for label, pre, threads in (("one thread", [], "1"), ("two threads", [], "2"),
                                ("2 MPI ranks", ["mpirun", "--oversubscribe", "-np", "2"], "1")):
        if pre and shutil.which("mpirun") is None:
            continue
        out = os.path.join(TMP, "stack_" + label.replace(" ", "_"))
        p = subprocess.run(pre + [XDYNA, "i=" + deck, "outdir=" + out], env=dict(env, OMP_NUM_THREADS=threads),
                           capture_output=True, text=True, preexec_fn=one_mb, cwd=ROOT)
        record(f"stack limit: 120,000 shells with contact run 2 cycles on {label} with a 1 MB stack",
               p.returncode == 0 and "normal termination" in p.stdout, f"rc={p.returncode} {p.stderr[-300:]}")


@pytest.mark.slow(20)
def test_mpi_deck_read_by_rank0():
    """Under MPI rank 0 alone opens the deck and its includes, and every
    rank takes their text from it (issue 32: one process reads a deck on a
    cluster's shared file system; a deck on a disk only rank 0's node sees
    runs). The tube crush with its nodes in an included file one folder
    down, on 2 ranks launched in two folders (MPMD): rank 0 where the deck
    is, rank 1 in an empty one, the deck named by a relative path. Had rank
    1 opened the files itself it would not find them and the run would stop
    or hang (before: it hung, the other rank waiting in a collective;
    tried). The motion must be the serial run's bitwise, energies to 1e-12
    (same_dynamics)."""
    if mpi_missing():
        return
    d = os.path.join(TMP, "deck_rank0")
    shutil.rmtree(d, ignore_errors=True)
    here, empty = os.path.join(d, "deck"), os.path.join(d, "elsewhere")
    os.makedirs(os.path.join(here, "sub"))
    os.makedirs(empty)
    text = open(os.path.join(ROOT, "input_decks/contact/tube_crush.k")).read()
    a, b = text.index("*NODE\n"), text.index("*ELEMENT_SHELL")
    with open(os.path.join(here, "sub", "nodes.k"), "w") as fh:
        fh.write("*KEYWORD\n" + text[a:b] + "*END\n")
    with open(os.path.join(here, "main.k"), "w") as fh:
        fh.write(text[:a] + "*INCLUDE\nsub/nodes.k\n" + text[b:])
    extra = ["endtim=0.0005"]
    p0, serial = run_deck(os.path.join(here, "main.k"), "deck_rank0_serial", extra=extra)
    out = os.path.join(d, "out")
    args = ["i=main.k", "outdir=" + out, *extra]
    env = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
    # (a hang ended after 2 minutes: the run takes under 2 s)
    p = run(["timeout", "120", "mpirun", "--oversubscribe", "-np", "1", "--wdir", here, XDYNA, *args, ":",
             "-np", "1", "--wdir", empty, XDYNA, *args], env=env)
    ok, msg = (False, (p0.stderr + p.stdout + p.stderr)[-400:]) if p.returncode or p0.returncode \
        else same_dynamics(serial, out)
    record("a deck and its include read by rank 0 for every rank: 2 ranks, rank 1 in a folder without them, give "
           f"the serial motion bitwise, energies to 1e-12 (rc {p.returncode})", ok, msg)
    # a restart dump that rank 1 cannot read (named relative to rank 0's
    # folder): every rank stops with exit 1, rank 1 naming its failure;
    # before, rank 1 stopped alone and rank 0 waited for it (a hang)
    dumped = os.path.join(d, "dumped")
    with open(os.path.join(here, "main.k")) as fh:
        text = fh.read()
    with open(os.path.join(here, "main.k"), "w") as fh:
        fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n*DATABASE_BINARY_D3DUMP\n         0\n", 1))
    p1 = run([XDYNA, "i=" + os.path.join(here, "main.k"), "outdir=" + dumped, "endtim=0.0002"])
    shutil.copy(os.path.join(dumped, "d3dump.h5"), os.path.join(here, "d3dump.h5"))
    args = ["r=d3dump.h5", "endtim=0.0004"]
    p = run(["timeout", "120", "mpirun", "--oversubscribe", "-np", "1", "--wdir", here, XDYNA, *args, ":",
             "-np", "1", "--wdir", empty, XDYNA, *args], env=env)
    named = "xdyna: r=d3dump.h5: the dump does not exist (rank 1)" in p.stderr
    record(f"a restart dump only rank 0 can read: every rank stops, exit 1 (got {p.returncode}), rank 1 naming "
           "why", p1.returncode == 0 and p.returncode == 1 and named, (p1.stderr + p.stderr)[-400:])
