"""Materials: the plastic returns against closed forms, the Taylor bar, failure
and erosion of shells and solids.

Each check states its tolerance and why (tests/README.md: how to run
and add tests)."""
import pytest

from xdtest import *  # noqa: F401,F403 (the shared helpers and imports)


STEEL = dict(E=200e9, nu=0.3, rho=7850.0, sy=250e6, Et=2e9)


def tension_path(out, h=0.01):
    """Log strain and Cauchy stress of the one-element tension decks: the top
    face's internal force is sum m a_z (the accelerations are those of the
    element forces), over the current cross-section."""
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        n = f["nodout"]
        t = n["time"][:]
        az, x, y, z = n["z_acceleration"][:], n["x_coordinate"][:], n["y_coordinate"][:], n["z_coordinate"][:]
    area = (x.max(1) - x.min(1)) * (y.max(1) - y.min(1))
    sig = -STEEL["rho"] * h ** 3 / 8 * az.sum(1) / area
    return t, np.log(z.mean(1) / h), sig


def uniaxial_1d(eps, beta, yield_of, hk):
    """Closed-form uniaxial return mapping on a strain path: elastic
    predictor, yield |sigma - alpha| = yield_of(ep), kinematic modulus hk."""
    E = STEEL["E"]
    s = al = ep = 0.0
    out = np.empty(len(eps))
    prev = 0.0
    for k, e in enumerate(eps):
        s += E * (e - prev)
        prev = e
        xi = s - al
        if abs(xi) > yield_of(ep):
            lo, hi = 0.0, abs(xi) / E
            for _ in range(80):
                mid = 0.5 * (lo + hi)
                if abs(xi) - (E + hk) * mid - yield_of(ep + mid) > 0:
                    lo = mid
                else:
                    hi = mid
            s -= E * lo * np.sign(xi)
            al += hk * lo * np.sign(xi)
            ep += lo
        out[k] = s
    return out


@pytest.mark.slow(24)
def test_plasticity():
    """One hexahedron under uniaxial stress against the closed-form
    stress-strain path: bilinear isotropic and kinematic hardening with a load
    reversal (Bauschinger: reverse yield at sigma_max - 2 sigma_y), a
    tabulated yield curve, and Cowper-Symonds scaling of the yield stress.
    0.5% (the issue's figure): of the stress where it flows, of the path's
    peak for the reversals (the elastic turn-arounds pass through zero)."""
    E, sy, Et = STEEL["E"], STEEL["sy"], STEEL["Et"]
    Ep = E * Et / (E - Et)
    decks = {}
    for d in ("tension_mat003_iso", "tension_mat003_kin", "tension_mat003_iso_rev", "tension_mat024_curve",
              "tension_mat024_rate"):
        p, out = run_deck(f"input_decks/verify/{d}.k", d)
        record(f"deck {d} runs (exit 0)", p.returncode == 0, p.stderr[-300:])
        if p.returncode != 0:
            return
        decks[d] = tension_path(out)
        g = glstat(out)
        # these runs start from rest: the energy ratio total / (E0 + W) is
        # ill-conditioned while W is still near zero, so the imbalance is
        # measured against the largest E0 + W of the run
        w = g["total_energy"][0] + g["external_work"]
        dev = np.max(abs(g["total_energy"] - w)) / np.max(abs(w))
        record(f"{d}: plastic work balances the prescribed motion's work (within 1% of it, {dev:.1e})",
               dev < 0.01)
    t, e, s = decks["tension_mat003_iso"]
    ref = uniaxial_1d(np.linspace(0, e[-1], 20001), 1.0, lambda ep: sy + Ep * ep, 0.0)
    ref = np.interp(e, np.linspace(0, e[-1], 20001), ref)
    k = e > 0.005
    err = np.max(abs(s[k] / ref[k] - 1))
    record(f"*MAT_003 isotropic: flow stress within 0.5% of sigma_y + Ep eps_p ({err:.1e})", err < 0.005)
    # the reversal decks follow u(t): 0 -> 0.3 mm at 3 ms -> -0.3 mm at 9 ms
    tt = np.linspace(0, 8e-3, 160001)
    ee = np.log(1 + np.interp(tt, [0, 3e-3, 9e-3], [0, 3e-4, -3e-4]) / 0.01)
    for d, beta in (("tension_mat003_kin", 0.0), ("tension_mat003_iso_rev", 1.0)):
        t, e, s = decks[d]
        ref = np.interp(t, tt, uniaxial_1d(ee, beta, lambda ep, b=beta: sy + b * Ep * ep, (1 - beta) * Ep))
        err = np.max(abs(s - ref)) / np.max(abs(ref))
        record(f"*MAT_003 BETA {beta:g}: tension and reversal within 0.5% of the closed form ({err:.1e})",
               err < 0.005)
    # kinematic: compression flows at a smaller stress than isotropic
    record("*MAT_003: kinematic hardening shows the Bauschinger effect (smaller reverse stress)",
           decks["tension_mat003_kin"][2].min() > 0.8 * decks["tension_mat003_iso_rev"][2].min())
    t, e, s = decks["tension_mat024_curve"]
    epc, syc = [0, 0.01, 0.03, 0.1], [250e6, 300e6, 330e6, 360e6]
    grid = np.linspace(0, e[-1], 20001)
    ref = np.interp(e, grid, uniaxial_1d(grid, 1.0, lambda ep: np.interp(ep, epc, syc), 0.0))
    k = e > 0.005
    err = np.max(abs(s[k] / ref[k] - 1))
    record(f"*MAT_024 with LCSS: flow stress within 0.5% of the curve ({err:.1e})", err < 0.005)
    t, e, s = decks["tension_mat024_rate"]
    with h5py.File(os.path.join(TMP, "tension_mat024_rate", "thist.h5"), "r") as f:
        x = f["nodout/x_coordinate"][:]
    lat = np.log((x.max(1) - x.min(1)) / 0.01)
    ez, ex = np.gradient(e, t), np.gradient(lat, t)
    m = (ez + 2 * ex) / 3
    rate = np.sqrt(2 / 3 * ((ez - m) ** 2 + 2 * (ex - m) ** 2))
    fac = 1 + (rate / 40.0) ** (1 / 5.0)
    ep = (E * e - fac * sy) / (E + fac * Ep)
    ref = fac * (sy + Ep * ep)
    k = e > 0.01
    err = np.max(abs(s[k] / ref[k] - 1))
    record(f"*MAT_024 Cowper-Symonds: yield scaled by 1 + (rate/C)^(1/P) within 0.5% ({err:.1e}, "
           f"factor {fac[k].mean():.3f})", err < 0.005)


@pytest.mark.slow(20)
def test_taylor_bar():
    """Taylor bar (copper, 227 m/s onto a frictionless wall, 80 us): final
    length within 1.5% of 21.45 mm and foot radius within 3% of 7.2 mm (the
    issue's figures), on two meshes, the finer closer in length; energy ratio
    within 2% (plastic work is internal energy; the wall takes the rest)."""
    res = {}
    for d in ("taylor_bar_coarse", "taylor_bar_fine"):
        p, out = run_deck(f"input_decks/verify/{d}.k", d)
        record(f"deck {d} runs (exit 0)", p.returncode == 0, p.stderr[-300:])
        if p.returncode != 0:
            return
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            n = f["nodout"]
            z, x, y = n["z_coordinate"][-1, :], n["x_coordinate"][-1, :], n["y_coordinate"][-1, :]
        length, foot = z[0] * 1e3, np.hypot(x[1:], y[1:]).max() * 1e3
        res[d] = length
        record(f"{d}: final length within 1.5% of 21.45 mm ({length:.3f} mm, {(length / 21.45 - 1) * 100:+.2f}%)",
               abs(length / 21.45 - 1) < 0.015)
        record(f"{d}: foot radius within 3% of 7.2 mm ({foot:.3f} mm, {(foot / 7.2 - 1) * 100:+.2f}%)",
               abs(foot / 7.2 - 1) < 0.03)
        dev = np.max(abs(glstat(out)["energy_ratio"] - 1))
        record(f"{d}: energy ratio within 2% ({dev:.1e})", dev < 0.02)
    record("Taylor bar: the finer mesh is closer to the reference length",
           abs(res["taylor_bar_fine"] - 21.45) < abs(res["taylor_bar_coarse"] - 21.45))


def sphere_plate_deck(v=300.0, fail=0.15, tend=2e-4, nsp=4, R=0.008):
    """A rigid sphere (radius 8 mm, 96 shells of a cube projected on it,
    7850 kg/m3 as 1 mm shells) at v onto a clamped 1 mm steel plate (40 x 40
    mm, 16 x 16 shells, *MAT_024 300 MPa, tangent 1 GPa, FAIL as given),
    surface-to-surface contact."""
    L = ["*KEYWORD", "*TITLE", "a rigid sphere through an eroding plate", "*CONTROL_TERMINATION", f"{tend:10.3e}",
         "*DATABASE_GLSTAT", " 2.000e-06", "*DATABASE_MATSUM", " 2.000e-06", "*DATABASE_BINARY_D3PLOT", " 1.000e-05",
         "*SECTION_SHELL", "         1         2         1         3", "     0.001     0.001     0.001     0.001",
         "*SECTION_SHELL", "         2         2         1         2", "     0.001     0.001     0.001     0.001",
         "*MAT_PIECEWISE_LINEAR_PLASTICITY", f"         1      7850     2e+11       0.3     3e+08     1e+09{fail:10.4g}",
         "*MAT_RIGID", "         2      7850     2e+11       0.3",
         "*PART", "plate", "         1         1         1", "*PART", "sphere", "         2         2         2", "*NODE"]
    n, h = 16, 0.04 / 16
    nid, pl = 0, {}
    for j in range(n + 1):
        for i in range(n + 1):
            nid += 1
            pl[i, j] = nid
            L.append(f"{nid:8d}{-0.02 + i*h:16.9e}{-0.02 + j*h:16.9e}{0.0:16.9e}       0       0")
    # cube-sphere
    nid, quads = cube_sphere(L, nid, R, R + 0.0015, nsp)
    L.append("*ELEMENT_SHELL")
    e = 0
    for j in range(n):
        for i in range(n):
            e += 1
            L.append(f"{e:8d}       1{pl[i, j]:8d}{pl[i + 1, j]:8d}{pl[i + 1, j + 1]:8d}{pl[i, j + 1]:8d}")
    for c in quads:
        e += 1
        L.append(f"{e:8d}       2" + "".join(f"{x:8d}" for x in c))
    edge = [pl[i, j] for j in range(n + 1) for i in range(n + 1) if i in (0, n) or j in (0, n)]
    L += ["*SET_NODE_LIST", "         1"] + [f"{x:10d}" for x in edge]
    L += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         1         1         1"]
    L += ["*INITIAL_VELOCITY_GENERATION", "         2         2       0.0       0.0       0.0" + f"{-v:10.4g}",
          "       0.0       0.0       0.0       0.0       0.0       0.0"]
    L += ["*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", "         2         1         3         3", "*END"]
    return "\n".join(l for l in L if l) + "\n"


def crush_deck(erode=1):
    """One 10 mm *MAT_024 shell squeezed flat in its plane (two nodes
    driven at 10 m/s toward the two held ones), *CONTROL_TERMINATION DTMIN
    0.1, *CONTROL_TIMESTEP ERODE as given."""
    L = ["*KEYWORD", "*TITLE", "a shell squeezed flat in its plane", "*CONTROL_TERMINATION", " 1.200e-03         0       0.1",
         "*CONTROL_TIMESTEP", f"       0.0       0.9         0       0.0       0.0         0{erode:10d}",
         "*SECTION_SHELL", "         1         2         1         3", "     0.001     0.001     0.001     0.001",
         "*MAT_PIECEWISE_LINEAR_PLASTICITY", "         1      7850     2e+11       0.3     3e+08     1e+09",
         "*PART", "strip", "         1         1         1", "*NODE",
         f"{1:8d}{0.0:16.9e}{0.0:16.9e}{0.0:16.9e}       1       7", f"{2:8d}{0.01:16.9e}{0.0:16.9e}{0.0:16.9e}       0       0",
         f"{3:8d}{0.01:16.9e}{0.01:16.9e}{0.0:16.9e}       0       0", f"{4:8d}{0.0:16.9e}{0.01:16.9e}{0.0:16.9e}       1       7",
         "*ELEMENT_SHELL", f"{1:8d}       1       1       2       3       4",
         "*SET_NODE_LIST", "         1", "         2         3",
         "*DEFINE_CURVE", "        50", f"{0.0:20.8e}{-10.0:20.8e}", f"{1.0:20.8e}{-10.0:20.8e}",
         "*BOUNDARY_PRESCRIBED_MOTION_SET", "         1         1         0        50       1.0",
         "*BOUNDARY_SPC_SET", "         1         0         0         0         1         1         1         1", "*END"]
    return "\n".join(L) + "\n"


def test_erosion():
    """Failure and erosion of shells (issue 33): FAIL of *MAT_024 and
    *MAT_ADD_EROSION. A rigid sphere at 300 m/s perforates a clamped 1 mm
    plate (FAIL 0.15): shells erode, each named in d3hsp with its internal
    energy, whose sum is glstat's eroded internal energy at the end (1e-6);
    the energy ratio, eroded energy counted, stays within 2% of 1 (what the
    contact's springs held when their segment eroded is lost: measured
    0.9%); the sphere leaves slower than it came; the penetration checker,
    honouring the eroded shells (d3plot.h5's shell_alive), finds no sphere
    node through the plate, while the same states read without it count
    pass-throughs where the shells were (the check can fail). Two ranks and
    a restart mid-erosion give the serial histories bitwise. *MAT_ADD_EROSION
    SIGVM on an elastic strip pulled at 0.1 m/s: it erodes when its von Mises
    stress E v t / L reaches SIGVM (5%); FAILTM erodes it at that time.
    Solids: test_solid_erosion."""
    p, out, path = run_text("erosion_sphere", sphere_plate_deck())
    if p.returncode != 0:
        record("erosion: the sphere through the plate runs", False, p.stderr[-300:])
        return
    log = open(os.path.join(out, "d3hsp")).read()
    named = [float(x) for x in re.findall(r"eroded at time\s+\S+, internal energy\s+(\S+)", log)]
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        eroded = f["glstat/eroded_internal_energy"][:]
        ratio = f["glstat/energy_ratio"][:]
        vz = f["matsum/z_momentum"][:, 1] / f["matsum/mass"][:, 1]
    dev = float(np.max(np.abs(ratio - 1)))
    record(f"erosion: the sphere perforates the plate, {len(named)} shells eroded and named; glstat's eroded internal "
           f"energy {eroded[-1]:.4f} J is their sum ({sum(named):.4f} J, 1e-6; 4 digits named: 1e-3); energy ratio "
           f"within 2% ({dev:.1e}); the sphere leaves at {-vz[-1]:.1f} m/s (from 300)",
           len(named) > 4 and abs(eroded[-1] / sum(named) - 1) < 1e-3 and dev < 0.02 and 0 < -vz[-1] < 299)
    hout = out + "_h5"
    p = run([XDYNA, "i=" + path, "outdir=" + hout, "h5plot=1"])
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import penetration as pen
    ok = p.returncode == 0
    if ok:
        worst, crossings, nst, _ = pen.check_run(hout)
        with h5py.File(os.path.join(hout, "d3plot.h5"), "r") as f:
            ids = f["mesh/node_ids"][:]
            shells, spart = f["mesh/shell_connectivity"][:], f["mesh/shell_part"][:]
            names = sorted(k for k in f["states"] if k != "time")
            X = np.array([f[f"states/{k}/coordinates"][:] for k in names], dtype=float)
            T = np.array([f[f"states/{k}/shell_thickness"][:] for k in names], dtype=float)
        _, blind = pen.check_states(pen.Surfaces(len(ids), shells.tolist(), spart.tolist()), X, T, ids,
                                    seg_part=list(spart))
        # (read without the eroded shells' flags the check once counted 6
        # crossings here; all six were the closest point of a torn shell
        # leaping sides, 19 mm off, which the checker no longer counts:
        # test_penetration_checker holds the flags on made-up states)
        record(f"erosion: no node passes through the plate over {nst} states ({crossings} pass-throughs; read "
               f"without the eroded shells' flags, {blind})", crossings == 0)
    else:
        record("erosion: the sphere run with d3plot.h5", False, p.stderr[-300:])
    # *CONTACT_ERODING_SURFACE_TO_SURFACE (card 4 ISYM EROSOP IADJ): the
    # automatic contact, which follows the erosion itself: the same run
    text = open(path).read().replace("*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n         2         1         3         3\n",
                                     "*CONTACT_ERODING_SURFACE_TO_SURFACE\n         2         1         3         3\n"
                                     "\n\n         0         1         1\n")
    p, eout, _ = run_text("erosion_sphere_eroding", text)
    ok, msg = (False, p.stderr[-300:]) if p.returncode else same_histories(out, eout)
    record("erosion: *CONTACT_ERODING_SURFACE_TO_SURFACE reads its card 4 and runs as the automatic contact (bitwise)",
           ok, msg)
    if shutil.which("mpirun") is not None:
        record("erosion: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)", *two_ranks_match(path, out))
        # (an eroding model runs with owned nodes: every rank erodes every
        # failed element, its energy and shape from the element's own rank)
        log = open(os.path.join(out + "_mpi2", "d3hsp")).read() if os.path.exists(os.path.join(out + "_mpi2", "d3hsp")) \
            else ""
        record("erosion: the eroding model runs with owned nodes under MPI (d3hsp's nodal state)",
               "nodal state: owned nodes" in log)
    ok, msg = restart_matches("erosion_rs", open(path).read(), 1e-5, 1e-4)
    record("erosion: a restart from 10 us (shells eroding since 4.9 us) ends as the uninterrupted run (bitwise)", ok, msg)
    # a strip pulled: *MAT_ADD_EROSION SIGVM, and FAILTM
    # (pulled at 0.1 m/s: the stress reaches SIGVM at 100 us, 56 steps of
    # 1.8 us, so the step's granularity is within 2%)
    for crit, card2, want in (("SIGVM", f"{0.0:10.3e}{0.0:10.3e}{2e8:10.3e}", 2e8 * 0.01 / (2e11 * 0.1)),
                              ("MXEPS", f"{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{1e-3:10.3e}",
                               0.01 * (math.exp(1e-3) - 1) / 0.1),
                              ("FAILTM", f"{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}"
                                         f"{0.0:10.3e}{6e-5:10.3e}", 6e-5)):
        L = ["*KEYWORD", "*TITLE", "a strip pulled until it erodes", "*CONTROL_TERMINATION", " 2.000e-04",
             "*SECTION_SHELL", "         1         2         1         2", "     0.001     0.001     0.001     0.001",
             "*MAT_ELASTIC", "         1      7850     2e+11       0.0",
             "*MAT_ADD_EROSION", "         1", card2,
             "*PART", "strip", "         1         1         1", "*NODE",
             f"{1:8d}{0.0:16.9e}{0.0:16.9e}{0.0:16.9e}       7       7", f"{2:8d}{0.01:16.9e}{0.0:16.9e}{0.0:16.9e}       0       0",
             f"{3:8d}{0.01:16.9e}{0.01:16.9e}{0.0:16.9e}       0       0", f"{4:8d}{0.0:16.9e}{0.01:16.9e}{0.0:16.9e}       7       7",
             "*ELEMENT_SHELL", f"{1:8d}       1       1       2       3       4",
             "*SET_NODE_LIST", "         1", "         2         3",
             "*DEFINE_CURVE", "        50", f"{0.0:20.8e}{0.1:20.8e}", f"{1.0:20.8e}{0.1:20.8e}",
             "*BOUNDARY_PRESCRIBED_MOTION_SET", "         1         1         0        50       1.0", "*END"]
        p, sout, _ = run_text("erosion_strip_" + crit.lower(), "\n".join(L) + "\n")
        m = re.search(r"shell 1 of part 1 eroded at time\s+([^,\s]+)", open(os.path.join(sout, "d3hsp")).read()) \
            if p.returncode == 0 else None
        t = float(m.group(1)) if m else float("nan")
        record(f"erosion: *MAT_ADD_EROSION {crit}: the strip erodes at {t * 1e6:.3f} us against {want * 1e6:.3f} us "
               f"(5%)", m is not None and abs(t / want - 1) < 0.05, p.stderr[-300:])
    # ERODE: the squeezed shell's step (its length along the squeeze, area
    # over its longest side) falls to DTMIN 0.1 of the first when 1 mm of
    # its 10 mm is left, at 0.9 ms: with ERODE 1 it erodes then (5%) and the
    # run ends normally; with ERODE 0 the run stops there (exit 2)
    p1, o1, _ = run_text("erosion_erode1", crush_deck(1))
    p0, _, _ = run_text("erosion_erode0", crush_deck(0))
    m = re.search(r"shell 1 of part 1 eroded at time\s+([^,\s]+)", open(os.path.join(o1, "d3hsp")).read()) \
        if p1.returncode == 0 else None
    t = float(m.group(1)) if m else float("nan")
    record(f"erosion: ERODE 1 erodes the shell squeezed flat when its step reaches DTMIN x the first, at "
           f"{t * 1e3:.4f} ms against 0.9 ms (5%), and the run ends normally; ERODE 0 stops it (exit {p0.returncode})",
           p1.returncode == 0 and m is not None and abs(t / 9e-4 - 1) < 0.05 and p0.returncode == 2
           and "fell below DTMIN" in p0.stderr, p1.stderr[-300:])


def solid_cube_deck(mat, tend):
    """The unit cube of tension_mat024_curve.k (10 mm, symmetry planes at x,
    y, z = 0, its top face pulled along z at a velocity ramped to 0.1 m/s
    over 0.2 ms) with the material cards `mat` and end time tend."""
    src = open(os.path.join(ROOT, "input_decks/verify/tension_mat024_curve.k")).read()
    head, rest = src.split("\n*MAT_PIECEWISE_LINEAR_PLASTICITY\n", 1)
    rest = rest.split("\n*PART\n", 1)[1]
    head = head.replace("     0.005         0", f"{tend:10.3e}         0", 1)
    return head + "\n" + mat + "*PART\n" + rest


def test_solid_erosion():
    """Failure and erosion of solids (issue 33 deliverable 1): a solid that
    fails is computed frozen (on its coordinates at erosion, at rest: no
    force, no step), its internal energy booked as eroded, named in d3hsp
    and flagged in the states. The 10 mm cube pulled along z (ramped to 0.1
    m/s) with *MAT_024 (SIGY 250 MPa, ETAN 0, FAIL 0.02) erodes when its
    effective plastic strain, ln(1 + u/L) - SIGY/E in uniaxial stress,
    reaches FAIL (2%: the ramp's stress wave and the step's granularity);
    elastic with *MAT_ADD_EROSION SIGP1 400 MPa, when E ln(1 + u/L) reaches
    it (5%); glstat's eroded internal energy is the eroded element's (its
    value named at erosion, and its last forces' half step, within 1%); the
    run goes on to its end with no element left. The Taylor bar with FS 0.5
    (*MAT_003) erodes at its impact end: the total energy with the eroded
    share within 2% of the initial, d3plot.h5's solid_alive 0 for each
    eroded solid and only those; two ranks and a restart mid-erosion give the
    serial histories bitwise. ERODE: the elastic cube (nu 0) squeezed at
    10 m/s erodes when its step falls below DTMIN 0.7 times the first,
    h / (qd + sqrt(qd^2 + c^2)) with c = c0 sqrt(h/L) and the bulk
    viscosity's qd = 1.5 v + 0.06 c, at the height that law gives (2%), the
    cycle where ERODE 0 stops the run (exit 2); the run then ends normally,
    the eroded energy in glstat (1%: the last forces' half step), the energy
    ratio within 1%. Contact on eroding solids:
    test_solid_erosion_contact."""
    E, sy, L, fail = 2e11, 2.5e8, 0.01, 0.02

    def erosion_time(strain):
        # u(t) = 1e-5 + 0.1 (t - 2e-4) m after the ramp
        return 2e-4 + (L * (math.exp(strain) - 1) - 1e-5) / 0.1

    # the strain criteria on the elastic cube (nu 0.3) in uniaxial stress,
    # its axial logarithmic strain e = ln(1 + u/L) and the lateral ones -nu
    # e (the rate form's): MXEPS on e, EFFEPS on 2/3 (1 + nu) e, VOLEPS on
    # (1 - 2 nu) e, MNEPS on -nu e, EPSSH on (1 + nu) e / 2 (2%: the ramp's
    # wave and the step)
    ela2 = "*MAT_ELASTIC\n         1      7850 2.000e+11       0.3\n*MAT_ADD_EROSION\n"
    ela = ela2 + "         1\n"
    cases = (("*MAT_024 FAIL 0.02", "*MAT_PIECEWISE_LINEAR_PLASTICITY\n"
              f"         1      7850{E:10.3e}       0.3{sy:10.3e}{0.0:10.3e}{fail:10.3e}\n",
              erosion_time(fail + sy / E), 0.02, 3e-3),
             ("*MAT_ADD_EROSION SIGP1 400 MPa", ela + f"{0.0:10.3e}{4e8:10.3e}\n", erosion_time(4e8 / E), 0.05, 5e-4),
             ("*MAT_ADD_EROSION MXEPS 0.003", ela + f"{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{3e-3:10.3e}\n",
              erosion_time(3e-3), 0.02, 6e-4),
             ("*MAT_ADD_EROSION EFFEPS 0.003", ela2 + f"         1{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{3e-3:10.3e}\n",
              erosion_time(3e-3 / (2 / 3 * 1.3)), 0.02, 6e-4),
             ("*MAT_ADD_EROSION VOLEPS 0.0012", ela2 + f"         1{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}"
              f"{1.2e-3:10.3e}\n", erosion_time(1.2e-3 / 0.4), 0.02, 6e-4),
             ("*MAT_ADD_EROSION MNEPS -0.0009", ela2 + f"         1{0.0:10.3e}{0.0:10.3e}{-9e-4:10.3e}\n",
              erosion_time(9e-4 / 0.3), 0.02, 6e-4),
             ("*MAT_ADD_EROSION EPSSH 0.00195", ela + f"{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{0.0:10.3e}{1.95e-3:10.3e}\n",
              erosion_time(1.95e-3 / 0.65), 0.02, 6e-4))
    for label, mat, want, tol, tend in cases:
        p, out, _ = run_text("solid_erosion_" + "_".join(label.split()[1:3]).lower().replace(".", ""),
                             solid_cube_deck(mat, tend))
        log = open(os.path.join(out, "d3hsp")).read() if os.path.exists(os.path.join(out, "d3hsp")) else ""
        m = re.search(r"solid 1 of part 1 eroded at time\s+([^,\s]+), internal energy\s+(\S+)", log)
        ok = p.returncode == 0 and m is not None
        t = float(m.group(1)) if m else float("nan")
        detail = p.stderr[-300:]
        if ok:
            with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
                er = f["glstat/eroded_internal_energy"][-1]
                tt = f["glstat/time"][:]
            # (d3hsp names the energy at erosion; the element's last forces
            # still act over the velocity update that follows, and the
            # frozen pass of the next cycle books that half step's work
            # too: a step of about 200 from the start, up to 1% more)
            ok = abs(t / want - 1) < tol and 0 <= er / float(m.group(2)) - 1 < 0.01 and tt[-1] > 0.99 * tend
            detail = (f"eroded at {t * 1e3:.4f} ms against {want * 1e3:.4f} ms ({t / want - 1:+.2%}); glstat's "
                      f"eroded internal energy {er:.4e} J, named {m.group(2)}; the run reached {tt[-1] * 1e3:.3f} ms")
        record(f"solid erosion: the pulled cube with {label} erodes at its criterion ({tol:.0%}), its energy "
               f"booked, the run going on with no element left: {detail}", ok)
    # the Taylor bar (*MAT_003, FS 0.5) against the rigid wall
    src = open(os.path.join(ROOT, "input_decks/verify/taylor_bar_coarse.k")).read()
    card = "         1      8930 1.170e+11      0.35 4.000e+08 1.000e+08         1\n"
    assert card in src
    deck = src.replace(card, card + "         0         0       0.5\n").replace(
        "*END", "*DATABASE_BINARY_D3PLOT\n 1.000e-05\n*END")
    p, out, path = run_text("solid_erosion_taylor", deck)
    if p.returncode != 0:
        record("solid erosion: the Taylor bar with FS runs", False, p.stderr[-300:])
        return
    log = open(os.path.join(out, "d3hsp")).read()
    named = re.findall(r"solid (\d+) of part 1 eroded at time", log)
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        total, e0 = f["glstat/total_energy"][:], f["glstat/kinetic_energy"][0]
        er = f["glstat/eroded_internal_energy"][-1]
    dev = float(np.max(np.abs(total / e0 - 1)))
    hout = out + "_h5"
    q = run([XDYNA, "i=" + path, "outdir=" + hout, "h5plot=1"])
    alive_ok = False
    if q.returncode == 0:
        with h5py.File(os.path.join(hout, "d3plot.h5"), "r") as f:
            last = sorted(k for k in f["states"] if k != "time")[-1]
            alive = f[f"states/{last}/solid_alive"][:]
            ids = f["mesh/solid_ids"][:]
        alive_ok = sorted(ids[alive == 0].tolist()) == sorted(int(x) for x in named)
    record(f"solid erosion: the Taylor bar with FS 0.5 erodes {len(named)} solids at its impact end, each named; "
           f"total energy, the eroded {er:.2f} J in it, within 2% of the initial {e0:.2f} J ({dev:.1e}); d3plot.h5's "
           f"solid_alive is 0 for exactly those: {alive_ok}", len(named) > 0 and dev < 0.02 and alive_ok)
    if shutil.which("mpirun") is not None:
        record("solid erosion: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)", *two_ranks_match(path, out))
    ok, msg = restart_matches("solid_erosion_rs", deck, 2e-5)
    first = float(re.search(r"eroded at time\s+(\S+),", log).group(1))
    record(f"solid erosion: a restart from 20 us (solids eroding since {first * 1e6:.2f} us) ends as the "
           f"uninterrupted run (bitwise)", ok and first < 2e-5, msg)
    # ERODE: the cube squeezed at 10 m/s, uniaxial (nu 0, symmetry planes):
    # h = L - v t, le = h, rho = rho0 L / h, c = c0 sqrt(h / L)
    v, ro = 10.0, 7850.0
    c0 = math.sqrt(E / ro)
    texts = {}
    for erode in (1, 0):
        d = solid_cube_deck("*MAT_ELASTIC\n         1      7850 2.000e+11       0.0\n", 1.2e-3)
        d = d.replace(f"{1.2e-3:10.3e}         0", f"{1.2e-3:10.3e}         0       0.7")
        d = d.replace("*CONTROL_TIMESTEP\n         0       0.9",
                      f"*CONTROL_TIMESTEP\n         0       0.9         0         0         0         0{erode:10d}")
        d = d.replace("      0.00000000e+00      0.00000000e+00\n      2.00000000e-04      1.00000000e-01\n"
                      "      1.00000000e+00      1.00000000e-01",
                      f"      0.00000000e+00{-v:20.8e}\n      1.00000000e+00{-v:20.8e}")
        texts[erode] = d
    p1, o1, _ = run_text("solid_erode1", texts[1])
    p0, _, _ = run_text("solid_erode0", texts[0])
    log1 = open(os.path.join(o1, "d3hsp")).read() if p1.returncode == 0 else ""
    m1 = re.search(r"solid 1 of part 1 eroded at time\s+(\S+), internal energy\s+(\S+)", log1)
    m0 = re.search(r"error termination at time\s+(\S+), cycle", p0.stderr)
    if m1 is None or m0 is None:
        record("solid erosion: ERODE 1 erodes the squeezed cube, ERODE 0 stops the run", False,
               (p1.stderr + p0.stderr)[-300:])
        return

    def step(h):
        c = c0 * math.sqrt(h / L)
        qd = 1.5 * v + 0.06 * c
        return h / (qd + math.sqrt(qd * qd + c * c))
    lo, hi = 1e-5 * L, L
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if step(mid) < 0.7 * L / c0 else (lo, mid)
    want = (L - hi) / v
    t1, t0 = float(m1.group(1)), float(m0.group(1))
    with h5py.File(os.path.join(o1, "thist.h5"), "r") as f:
        er, dev = f["glstat/eroded_internal_energy"][-1], float(np.max(np.abs(f["glstat/energy_ratio"][:] - 1)))
    record(f"solid erosion: ERODE 1 erodes the cube squeezed at 10 m/s when its step reaches DTMIN 0.7 x the first, at "
           f"{t1 * 1e3:.4f} ms against {want * 1e3:.4f} ms from the step's law (2%: {t1 / want - 1:+.2%}), where ERODE 0 "
           f"stops the run ({t0 * 1e3:.4f} ms, exit {p0.returncode}); the run ends normally, glstat's eroded energy "
           f"{er:.4g} J against the named {float(m1.group(2)):.4g} J (1%), energy ratio within 1% ({dev:.1e})",
           abs(t1 / want - 1) < 0.02 and t1 == t0 and p0.returncode == 2 and p1.returncode == 0
           and abs(er / float(m1.group(2)) - 1) < 0.01 and dev < 0.01)
