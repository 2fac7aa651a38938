"""Elements: hexahedra, Belytschko-Tsay shells (hourglass forms, step length,
thickness change, mass scaling) and beams against closed forms and
conservation laws.

Each check states its tolerance and why (tests/README.md: how to run
and add tests)."""
import pytest

from xdtest import *  # noqa: F401,F403 (the shared helpers and imports)


def shell_path_error(out, share):
    """Largest relative error, past 0.5% strain, of the stress of the
    10 mm x 1 mm sheet pulled at nodes 2 and 3 (*MAT_003, E 200 GPa, yield
    250 MPa, tangent 2 GPa) against the bilinear uniaxial closed form.  The
    edge force is the sum of m a over the two pulled nodes, whose lumped masses
    are share[0] and share[1] of rho h^2 t; returns the error and the
    accelerations."""
    E, sy, Et, h, th = 200e9, 250e6, 2e9, 0.01, 0.001
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        ax, x, y = f["nodout/x_acceleration"][:], f["nodout/x_coordinate"][:], f["nodout/y_coordinate"][:]
    force = -7850.0 * th * h * h * (share[0] * ax[:, 0] + share[1] * ax[:, 1])
    sig = force / ((y[:, 1] - y[:, 0]) * th)
    eps = np.log(x[:, 0] / h)
    Ep = E * Et / (E - Et)
    ref = np.where(E * eps > sy, sy + Ep * (E * eps - sy) / (E + Ep), E * eps)
    k = eps > 0.005
    return (np.max(abs(sig[k] / ref[k] - 1)) if k.any() else 1.0), ax


@pytest.mark.xdist_group("bar_impact")
def test_bar_impact(bar_impact_run):
    """(a) Elastic bar (nu = 0), moving at v0 and stopped at x = 0: the front
    runs at c = sqrt(E/rho) and carries sigma = rho c v0. Tolerance 2% (the
    issue's): the front is smeared over a few elements by bulk viscosity, and
    arrival is taken where the velocity has dropped by half."""
    p, out = bar_impact_run
    record("deck bar_impact runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    E, rho, v0 = 200e9, 7850.0, 10.0
    c = np.sqrt(E / rho)
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        t = f["nodout/time"][:]
        x0 = f["nodout/x_coordinate"][0, :]
        vx = f["nodout/x_velocity"][:]
        ux = f["nodout/x_displacement"][:]
    for d in (0.5, 0.75):
        j = int(np.argmin(abs(x0 - d)))
        v = vx[:, j]
        k = int(np.argmax(v > -v0 / 2))
        tc = t[k - 1] + (t[k] - t[k - 1]) * (-v0 / 2 - v[k - 1]) / (v[k] - v[k - 1])
        err = tc / (d / c) - 1
        record(f"bar: wave arrival at x = {d} within 2% of x/c ({err * 100:+.3f}%)", abs(err) < 0.02)
    j1, j2 = int(np.argmin(abs(x0 - 0.2))), int(np.argmin(abs(x0 - 0.3)))
    sigma = E * (ux[-1, j2] - ux[-1, j1]) / (x0[j2] - x0[j1])
    err = sigma / (-rho * c * v0) - 1
    record(f"bar: stress behind the front within 2% of rho c v0 ({err * 100:+.3f}%)", abs(err) < 0.02)
    g = glstat(out)
    dev = np.max(abs(g["energy_ratio"] - 1))
    # no dissipation but bulk viscosity and hourglass work, both booked: 0.5%
    record(f"bar: energy ratio within 0.5% throughout ({dev:.2e})", dev < 0.005)
    # regression against the reviewed reference run (see tests/reference/README.md)
    # (the reference is the 64-bit build's; a 32-bit run is held to 1e-2 of
    # the peak, its stress front differs by 0.17% of the peak, measured, and
    # the zero sideways velocities to its round-off; its 32-bit steps end the
    # run 4 ns earlier, so the common times are compared)
    rtol = "1e-2" if SINGLE else "1e-4"
    q = run([THDIFF, out, os.path.join(ROOT, "tests", "reference", "bar_impact"), "--rtol", rtol,
             "--atol", str(roundoff(1e-9)), "--only", "glstat,nodout", "--common", *(["--overlap"] if SINGLE else [])])
    record(f"bar: time histories match the reference run (thdiff rtol {rtol} of peak)", q.returncode == 0,
           q.stdout[-600:])


def test_free_block():
    """(b) A free block translating and spinning: no external force, so total
    energy is constant; 1e-6 relative over 1e4 cycles (the issue's figure)."""
    p, out = run_deck("input_decks/verify/free_block_spin.k", "free_block_spin")
    record("deck free_block_spin runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    g = glstat(out)
    with open(os.path.join(out, "d3hsp")) as f:
        ncyc = [l for l in f if "cycles ....." in l]
    record("free block: ran 10000 cycles", bool(ncyc) and int(ncyc[-1].split()[-1]) == 10000, str(ncyc))
    te = g["total_energy"]
    dev = np.max(abs(te / te[0] - 1))
    record(f"free block: total energy constant to 1e-6 over 1e4 cycles ({dev:.2e})", dev < 1e-6)
    # momentum is conserved exactly by the assembly (internal forces sum to zero)
    v = np.stack([g["x_velocity"], g["y_velocity"], g["z_velocity"]])
    dv = np.max(abs(v - v[:, :1]))
    record(f"free block: centre-of-mass velocity constant to {roundoff(1e-9):.0e} m/s ({dv:.1e})", dv < roundoff(1e-9))


def test_prestressed():
    """(c) A column with its first-mode axial prestress released under SPCs:
    energy ratio within 0.5% (the issue's figure)."""
    p, out = run_deck("input_decks/verify/prestressed_block.k", "prestressed_block")
    record("deck prestressed_block runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    g = glstat(out)
    # stored energy: sigma0^2 V / (2E) * mean(cos^2) over the column; elements
    # take the stress at their centroid: 8 layers, midpoint rule
    zc = (np.arange(8) + 0.5) / 8
    e0 = (1e8 ** 2) / (2 * 200e9) * 0.05 * 0.05 * 0.2 * np.mean(np.cos(np.pi * zc / 2) ** 2)
    record(f"prestressed: initial internal energy = sigma^2 V / 2E ({g['internal_energy'][0]:.6g} vs {e0:.6g})",
           abs(g["internal_energy"][0] / e0 - 1) < roundoff(1e-12))
    dev = np.max(abs(g["energy_ratio"] - 1))
    record(f"prestressed: energy ratio within 0.5% throughout ({dev:.2e})", dev < 0.005)
    record("prestressed: the column moves (kinetic energy reaches 50% of the stored energy)",
           np.max(g["kinetic_energy"]) > 0.5 * e0)


def test_shells():
    """Belytschko-Tsay shells: a cantilever strip released in its first
    mode's velocity shape vibrates at the beam's first frequency
    f1 = (1.8751^2 / 2 pi) sqrt(E t^2 / (12 rho L^4)) within 3% (the issue's
    figure); elastic, so the energy ratio stays within 1e-6."""
    p, out = run_deck("input_decks/verify/shell_cantilever.k", "shell_cantilever")
    record("deck shell_cantilever runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        t, vz = f["nodout/time"][:], f["nodout/z_velocity"][:, 0]
    down = [t[i - 1] + (t[i] - t[i - 1]) * vz[i - 1] / (vz[i - 1] - vz[i]) for i in range(1, len(vz))
            if vz[i - 1] > 0 >= vz[i]]
    E, rho, th, L = 200e9, 7850.0, 0.002, 0.2
    f1 = 1.875104 ** 2 / (2 * np.pi) * np.sqrt(E * th ** 2 / (12 * rho * L ** 4))
    got = 1 / np.mean(np.diff(down)) if len(down) > 1 else 0.0
    record(f"shell cantilever: first frequency within 3% of beam theory ({(got / f1 - 1) * 100:+.2f}%)",
           abs(got / f1 - 1) < 0.03)
    dev = np.max(abs(glstat(out)["energy_ratio"] - 1))
    record(f"shell cantilever: energy ratio within {roundoff(1e-6):.0e} ({dev:.1e})", dev < roundoff(1e-6))
    # one shell in uniaxial plane stress, *MAT_003 isotropic: the closed-form
    # bilinear path to 0.5% (the figure); the thickness is held, so
    # the stress is the edge force over width x t0
    p, out = run_deck("input_decks/verify/shell_tension.k", "shell_tension")
    record("deck shell_tension runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    h = 0.01
    err, ax = shell_path_error(out, (0.25, 0.25))
    record(f"shell plane-stress plasticity: flow stress within 0.5% of the closed form ({err:.1e})", err < 0.005)
    # thickness change (ISTUPD): the force falls with the thickness, which
    # follows the width in plastic incompressibility (0.5%: the elastic part of
    # the thickness strain has nu = 0.3, not 0.5)
    p2, out2 = run_deck("input_decks/verify/shell_tension_thick.k", "shell_tension_thick")
    record("deck shell_tension_thick runs (exit 0)", p2.returncode == 0, p2.stderr[-300:])
    if p2.returncode == 0:
        with h5py.File(os.path.join(out2, "thist.h5"), "r") as f:
            ax2, y2 = f["nodout/x_acceleration"][:], f["nodout/y_coordinate"][:]
        ratio = ax2.sum(1)[-1] / ax.sum(1)[-1]
        thin = np.log((y2[-1, 1] - y2[-1, 0]) / h)
        record(f"shell thickness change: force ratio = exp(width strain) ({ratio:.5f} vs {np.exp(thin):.5f})",
               abs(ratio / np.exp(thin) - 1) < 0.005)
    # the same sheet as two triangles (N3 = N4): a uniaxial stress state is a
    # linear field, which the one-point strain rate of a degenerate quad
    # reproduces exactly, so the closed form holds to the quad's 0.5%.  The
    # lumped masses differ: node 2 has h^2/6 of the sheet, node 3 h^2/3.
    p3, out3 = run_deck("input_decks/verify/shell_tension_tri.k", "shell_tension_tri")
    record("deck shell_tension_tri runs (exit 0)", p3.returncode == 0, p3.stderr[-300:])
    if p3.returncode == 0:
        err3, _ = shell_path_error(out3, (1 / 6, 1 / 3))
        record(f"triangular shells (N3 = N4): plane-stress path within 0.5% of the closed form ({err3:.1e})",
               err3 < 0.005)


def test_shell_warped_spin():
    """A warped 2 x 2 shell patch (nodes 1 mm off its mean plane, 10 mm
    shells) spinning free about an in-plane axis for a quarter turn: a rigid
    motion, so the hourglass and internal energies must stay below 1e-5 of
    the kinetic energy (before the membrane hourglass rates left out the
    rigid spin of warped elements, the hourglass energy reached 1.4% of
    it) and the kinetic energy must stay within 1e-3. The deck takes the
    stiffness hourglass form (it says why: under the viscous form the
    spin's centrifugal load drives the corners' twist, an hourglass mode)."""
    p, out = run_deck("input_decks/verify/shell_warped_spin.k", "shell_warped_spin")
    record("warped shell spin runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    g = glstat(out)
    ke0 = g["kinetic_energy"][0]
    hg = np.max(abs(g["hourglass_energy"])) / ke0
    ie = np.max(abs(g["internal_energy"])) / ke0
    dke = abs(g["kinetic_energy"][-1] / ke0 - 1)
    record(f"warped shell spin: hourglass {hg:.1e} and internal {ie:.1e} of the kinetic energy (under 1e-5), "
           f"kinetic energy kept within 1e-3 ({dke:.1e})", hg < 1e-5 and ie < 1e-5 and dke < 1e-3)


def hourglass_modes_deck(path, hourglass, endtim, tssfac=0.1, speeds=(0.01, 0.01, 1.0), material=None,
                         controls=()):
    """Three free 10 mm steel shells, 1 mm thick, each started in one pure
    hourglass mode (corner pattern h = 1, -1, 1, -1; `speeds`, by default
    0.01 m/s): part 1 in-plane (x), part 2 out of plane (z), part 3
    rotation about x (1 rad/s). None of them strains the one point, so each
    mode answers to its own hourglass coefficient alone. `hourglass` is the
    *HOURGLASS card (None: no card, the parts take *CONTROL_HOURGLASS's
    defaults); `material` the material card (material 1) instead of
    *MAT_ELASTIC; `controls` further keyword lines. TSSFAC 0.1 keeps the
    modes many steps long."""
    L, h = 0.01, 0.001
    out = ["*KEYWORD", "*TITLE", "one shell per hourglass mode, free", "*CONTROL_TERMINATION",
           f"{endtim:10.4g}         0", "*CONTROL_TIMESTEP", f"         0{tssfac:10.3f}",
           "*DATABASE_GLSTAT", f"{endtim / 4000:10.4g}", "*DATABASE_MATSUM", f"{endtim / 4000:10.4g}",
           "*SECTION_SHELL", "         1         2         1         2", f"{h:10.4g}" * 4,
           *(material or ["*MAT_ELASTIC", "         1      7850     2e+11       0.3"]), *controls]
    if hourglass is not None:
        out += ["*HOURGLASS", hourglass]
    for p in (1, 2, 3):
        out += ["*PART", f"mode {p}", f"{p:10d}         1         1         0{int(hourglass is not None):10d}"]
    out.append("*NODE")
    pat, xy = [1, -1, 1, -1], [(0, 0), (L, 0), (L, L), (0, L)]
    for p in (1, 2, 3):
        out += [f"{4 * (p - 1) + k + 1:8d}{xy[k][0] + 3 * L * (p - 1):16.9e}{xy[k][1]:16.9e}{0.0:16.9e}"
                for k in range(4)]
    out.append("*ELEMENT_SHELL")
    out += [f"{p:8d}{p:8d}" + "".join(f"{4 * (p - 1) + k + 1:8d}" for k in range(4)) for p in (1, 2, 3)]
    out.append("*INITIAL_VELOCITY_NODE")
    out += [f"{k + 1:10d}{speeds[0] * pat[k]:10.4g}{0:10d}{0:10d}" for k in range(4)]
    out += [f"{k + 5:10d}{0:10d}{0:10d}{speeds[1] * pat[k]:10.4g}" for k in range(4)]
    out += [f"{k + 9:10d}{0:10d}{0:10d}{0:10d}{speeds[2] * pat[k]:10.4g}" for k in range(4)]
    out.append("*END")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def hourglass_mode_energies(out):
    """Kinetic and hourglass energy of each mode's shell (matsum's kinetic
    energy is translational; the rotating shell's is glstat's less the
    other two), with the times and the time step."""
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        ke, hg = f["matsum/kinetic_energy"][:], f["matsum/hourglass_energy"][:]
        ke[:, 2] = f["glstat/kinetic_energy"][:] - ke[:, 0] - ke[:, 1]
        return f["matsum/time"][:], ke, hg, f["glstat/time_step"][:]


def test_shell_hourglass_forms():
    """Belytschko-Tsay hourglass control, each form against its closed-form
    response (issue 31). One square shell of side L, mass m = rho h L^2 per
    node quarter, gamma = h (gamma.gamma = 4), B.B = 2/L^2: the stiffness
    at coefficient 1 of each mode is k1 = E h L^2/8 B.B (membrane),
    kappa G h^3/12 B.B (warping), E h^3 L^2/192 B.B (bending, on the rotary
    inertia m (h^2 + 3 L^2)/12), and its mass m/4. The stiffness form
    (IHQ 4) makes each mode a free oscillator, omega^2 = q k1/(m/4), which
    the central difference turns into (2/dt) asin(omega dt/2); the viscous
    form (IHQ 1, the default) a damper, qdot falling by (1 - 2 q omega1 dt)
    a step (omega1^2 = k1/(m/4)). Both are exact for these linear modes
    but for round-off, so the tolerance is 1e-4 on a frequency or a
    rate. Energy: the stiffness form keeps kinetic + hourglass energy, the
    viscous form turns the kinetic energy into hourglass work, both to 1e-9
    (round-off; before the fix the rotating shell's initial kinetic energy
    was taken from the spin after the first step, and its balance read
    1.6e-3, lambda dt)."""
    L, h, E, rho, nu = 0.01, 0.001, 2e11, 7850.0, 0.3
    G, m = E / (2 * (1 + nu)), rho * h * L * L / 4
    k1 = [E * h / 4, G * h ** 3 / (6 * L * L), E * h ** 3 / 96]
    m1 = [m / 4, m / 4, m * (h * h + 3 * L * L) / 12 / 4]
    names = ["membrane", "warping", "bending"]
    runs = {}
    # stiffness form, its three coefficients apart: QM 0.05, QB 0.02, QW 0.08
    for key, card, endtim in (("stiff", f"{1:10d}{4:10d}{0.05:10.3g}{0:10d}{0:10.1f}{0:10.1f}{0.02:10.3g}{0.08:10.3g}",
                               3e-3),
                              ("visc", f"{1:10d}{1:10d}{0.1:10.3g}{0:10d}{0:10.1f}{0:10.1f}{0.05:10.3g}{0.2:10.3g}",
                               1e-3),
                              ("default", None, 1e-3)):
        deck = os.path.join(TMP, f"hg_{key}.k")
        hourglass_modes_deck(deck, card, endtim)
        p, out = run_deck(deck, f"hg_{key}")
        record(f"hourglass modes ({key}) run (exit 0)", p.returncode == 0, p.stderr[-300:])
        if p.returncode != 0:
            return
        runs[key] = hourglass_mode_energies(out)
    t, ke, hg, dts = runs["stiff"]
    dt = dts[1]
    for i, q in enumerate([0.05, 0.08, 0.02]):
        k = ke[:, i]
        mins = [j for j in range(1, len(k) - 1) if k[j] <= k[j - 1] and k[j] < k[j + 1]]
        tm = [t[j] + 0.5 * (k[j - 1] - k[j + 1]) / (k[j - 1] - 2 * k[j] + k[j + 1]) * (t[1] - t[0]) for j in mins]
        w = np.sqrt(q * k1[i] / m1[i])
        wd = 2 / dt * np.arcsin(w * dt / 2)
        got = np.pi / np.mean(np.diff(tm)) if len(tm) > 2 else 0.0
        record(f"stiffness form (IHQ 4), {names[i]} mode at q {q}: omega {got:.6g} against {wd:.6g} "
               f"({len(tm)} half periods; within 1e-4)", abs(got / wd - 1) < 1e-4)
        bal = np.max(abs(k + hg[:, i] - k[0])) / k[0]
        record(f"stiffness form, {names[i]} mode: kinetic + hourglass energy kept within 1e-9 ({bal:.1e})",
               bal < 1e-9)
    for key, qs in (("visc", [0.1, 0.2, 0.05]), ("default", [0.1, 0.1, 0.1])):
        t, ke, hg, dts = runs[key]
        dt = dts[1]
        for i, q in enumerate(qs):
            k = ke[:, i]
            lam = 2 * q * np.sqrt(k1[i] / m1[i])
            want = -2 * np.log(1 - lam * dt) / dt
            sel = (k < 0.5 * k[0]) & (k > 1e-4 * k[0])
            got = -np.polyfit(t[sel], np.log(k[sel]), 1)[0] if sel.sum() > 3 else 0.0
            form = "viscous form (IHQ 1)" if key == "visc" else "no *HOURGLASS (IHQ 1 default, QM 0.1)"
            record(f"{form}, {names[i]} mode at q {q}: kinetic energy decays at {got:.6g}/s against {want:.6g} "
                   f"(within 1e-4)", abs(got / want - 1) < 1e-4)
            live = k > 1e-6 * k[0]
            mono = bool(np.all(np.diff(k[live]) <= 0))
            bal = np.max(abs(k + hg[:, i] - k[0])) / k[0]
            record(f"{form}, {names[i]} mode: no overshoot (kinetic energy falls every output), its loss booked "
                   f"as hourglass work within 1e-9 ({bal:.1e})", mono and bal < 1e-9)


def test_shell_hourglass_plastic_bound():
    """The stiffness form on a plastic material under *CONTROL_XDYNA_SHELL
    HGBOUND 1 (issue 28; the default since): each mode's
    generalized force is bounded at its coefficient times the mode's fully
    plastic value, Q_c = q Q_p, with (one square shell of side L, flow
    stress sy) Q_p = sy h L / 3 (membrane), sy h^2 / (2 sqrt 3) (warping),
    sy h^2 L / 12 (bending). The shells of hourglass_modes_deck on *MAT_024
    (elastic-perfectly plastic, sy 250 MPa; the modes leave the one point
    unstrained, so sy stays the flow stress), each started with about four
    times the energy its spring holds at the bound: the mode loads
    elastically (stiffness q k1) to Q_c, flows at Q_c until it stops, and
    then swings elastically between -Q_c and +Q_c, so its kinetic energy
    peaks at Q_c^2 / (2 q k1) from then on (the elastic-perfectly plastic
    oscillator). Within 2%: the central difference and the step's
    clipping at the bound round each peak by about (omega dt)^2 and one
    step's overshoot; the node moves 0.3% of L at most, so the geometry
    hardly changes. The work cut off by the bound is hourglass energy:
    kinetic + hourglass energy stays the initial kinetic energy within
    1e-6. The same shells on *MAT_ELASTIC are test_shell_hourglass_forms's
    free oscillators (no bound); with HGBOUND 0 (elastic springs without
    limit) the plastic shells' modes are free oscillators too: their
    kinetic energy comes back to its start (no work cut off). The bound is
    on without the card; the card's HGBOUND 1 where it acts nowhere is
    warned, the default there is not."""
    L, h, E, rho, nu, sy = 0.01, 0.001, 2e11, 7850.0, 0.3, 250e6
    G, m = E / (2 * (1 + nu)), rho * h * L * L / 4
    k1 = [E * h / 4, G * h ** 3 / (6 * L * L), E * h ** 3 / 96]
    qp = [sy * h * L / 3, sy * h * h / (2 * math.sqrt(3)), sy * h * h * L / 12]
    qs = [0.05, 0.08, 0.02]
    names = ["membrane", "warping", "bending"]
    inertia = [4 * m, 4 * m, 4 * m * (h * h + 3 * L * L) / 12]
    held = [q * c * c / (2 * k) for q, c, k in zip(qs, qp, k1)]
    speeds = [math.sqrt(2 * 4 * e / i) for e, i in zip(held, inertia)]
    card = f"{1:10d}{4:10d}{0.05:10.3g}{0:10d}{0:10.1f}{0:10.1f}{0.02:10.3g}{0.08:10.3g}"
    mat = ["*MAT_PIECEWISE_LINEAR_PLASTICITY", f"{1:10d}{rho:10.4g}{E:10.4g}{nu:10.4g}{sy:10.4g}{0.0:10.4g}"]
    deck = os.path.join(TMP, "hg_plastic_free.k")
    hourglass_modes_deck(deck, card, 2e-3, speeds=speeds, material=mat,
                         controls=["*CONTROL_XDYNA_SHELL", f"{0:10d}"])
    p, out = run_deck(deck, "hg_plastic_free")
    record("hourglass modes on a plastic material, HGBOUND 0, run (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    t, ke, hg, dts = hourglass_mode_energies(out)
    back = [float(np.max(ke[len(ke) // 2:, i]) / ke[0, i]) for i in range(3)]
    record(f"with HGBOUND 0 the plastic shells' hourglass springs stay elastic: each mode's kinetic energy "
           f"peaks again at its start within 1% ({', '.join(f'{b - 1:+.1e}' for b in back)}; the outputs sample "
           f"the membrane mode's period 56 times, so a peak is read up to 0.3% low; the bound would cut it to a "
           f"quarter; above it by round-off of the half-step velocities only)", all(0.99 < b < 1 + 1e-4 for b in back))
    deck = os.path.join(TMP, "hg_plastic.k")
    hourglass_modes_deck(deck, card, 2e-3, speeds=speeds, material=mat)      # the default: bounded
    p, out = run_deck(deck, "hg_plastic")
    record("hourglass modes on a plastic material run (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    t, ke, hg, dts = hourglass_mode_energies(out)
    with open(os.path.join(out, "d3hsp")) as f:
        log = f.read()
    record("no warning where the bound acts", "it acts nowhere" not in log)
    deck = os.path.join(TMP, "hg_elastic_bound.k")
    hourglass_modes_deck(deck, card, 1e-4, speeds=speeds, controls=["*CONTROL_XDYNA_SHELL", f"{1:10d}"])
    q, out_e = run_deck(deck, "hg_elastic_bound")
    with open(os.path.join(out_e, "d3hsp")) as f:
        elog = f.read()
    record("HGBOUND 1 on elastic shells only: d3hsp warns that it acts nowhere (nothing accepted silently)",
           q.returncode == 0 and "field HGBOUND 1: no shell has the stiffness-form hourglass" in elog, elog[-400:])
    deck = os.path.join(TMP, "hg_elastic_default.k")
    hourglass_modes_deck(deck, card, 1e-4, speeds=speeds)
    q, out_e = run_deck(deck, "hg_elastic_default")
    with open(os.path.join(out_e, "d3hsp")) as f:
        elog = f.read()
    record("the same elastic shells without the card: no warning (the default bound is not the user's choice)",
           q.returncode == 0 and "acts nowhere" not in elog and "bounded at its coefficient" not in elog, elog[-400:])
    deck = os.path.join(TMP, "hg_bad_bound.k")
    hourglass_modes_deck(deck, card, 1e-4, speeds=speeds, controls=["*CONTROL_XDYNA_SHELL", f"{2:10d}"])
    q, _ = run_deck(deck, "hg_bad_bound")
    record("HGBOUND 2: exit 1, the message names the file, line, keyword, field and value",
           q.returncode == 1 and all(w in q.stderr for w in ("hg_bad_bound.k", "CONTROL_XDYNA_SHELL", "HGBOUND 2")),
           q.stderr[-300:])
    record("d3hsp names the bound on the stiffness form of the plastic parts and the shells it acted on",
           "each mode bounded at its coefficient times its plastic capacity" in log
           and "in 3 of 3 shells" in log, log[-600:])
    for i in range(3):
        k = ke[:, i]
        first = next((j for j in range(1, len(k) - 1) if k[j] <= k[j - 1] and k[j] < k[j + 1]), None)
        peaks = [k[j] for j in range(max(first or 0, 1), len(k) - 1) if k[j] >= k[j - 1] and k[j] > k[j + 1]]
        got = float(np.median(peaks)) if first and len(peaks) > 2 else 0.0
        record(f"plastic bound, {names[i]} mode at q {qs[i]}: after the first stop its kinetic energy peaks at "
               f"{got:.5g} J against Q_c^2/(2 q k1) = {held[i]:.5g} J ({len(peaks)} peaks; within 2%), from "
               f"{k[0]:.4g} J", abs(got / held[i] - 1) < 0.02, f"first minimum at output {first}")
        bal = np.max(abs(k + hg[:, i] - k[0])) / k[0]
        record(f"plastic bound, {names[i]} mode: kinetic + hourglass energy kept within 1e-6 ({bal:.1e})",
               bal < 1e-6)


def clamped_plate_deck(path, v, nip=2, tssfac=0.9):
    """A 10 mm steel plate of 5 x 5 shells (1 mm), clamped along its edge
    (every dof), its 16 inner nodes given v m/s downwards: it vibrates
    elastically at large amplitude (v = 30: about 10 degrees of rotation
    at the edge), run for 200 us."""
    n = 6
    lines = ["*KEYWORD", "*TITLE", "clamped plate thrown into vibration", "*CONTROL_TERMINATION", "  2.0e-4",
             "*CONTROL_TIMESTEP", f"         0{tssfac:10.3g}", "*DATABASE_GLSTAT", "  1.0e-7",
             "*SECTION_SHELL", f"         1         2         1{nip:10d}", "     0.001     0.001     0.001     0.001",
             "*MAT_ELASTIC", "         1      7850 2.000e+11       0.3", "*PART", "plate", "         1         1         1",
             "*NODE"]
    nodes, elems = shell_grid(n, 1, 1, 0)
    lines += nodes + ["*ELEMENT_SHELL"] + elems
    edge = [1 + n * j + i for j in range(n) for i in range(n) if i in (0, n - 1) or j in (0, n - 1)]
    inner = [1 + n * j + i for j in range(n) for i in range(n) if not (i in (0, n - 1) or j in (0, n - 1))]
    lines += node_set(1, edge)
    lines += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         1         1         1"]
    for a in inner:
        lines += ["*INITIAL_VELOCITY_NODE", f"{a:10d}{0.0:10.3g}{0.0:10.3g}{-v:10.4g}"]
    lines.append("*END")
    return write_lines(path, lines)


def test_shell_step_length():
    """The shells' step length, *CONTROL_TIMESTEP ISDO as LS-DYNA's manual
    gives it. One free elastic shell (steel, E 200 GPa, nu 0.3, rho 7850)
    at rest: a parallelogram with sides 10 and 6 mm at 45 degrees (area
    42.43 mm^2, diagonals 14.85 and 7.15 mm) and a triangle of the same two
    sides. The first step must be TSSFAC 0.9 x L / c (rel 1e-6: the step
    is that expression in floating point):
    ISDO 0 area / longest side (the triangle's shortest altitude, twice
    that), 1 area / longest diagonal (triangle as 0), 2 max(shortest side,
    area / longest side) with the bar wave speed (the triangle's shortest
    side). Then a triangle-meshed cantilever struck at its free edge (a
    velocity jump that excites the highest modes) runs 4000 cycles at
    ISDO 0 with the energy ratio within 1e-3 of 1: the triangle's step
    (doubled on 2026-11-26, from half its altitude) is stable. Its margin,
    measured: at TSSFAC 0.95 this strip runs, at 1.0 it stops (velocities
    reverse within a step), and the same strip of quadrilaterals does the
    same at the same factors: the triangles' step has the quadrilaterals'
    margin."""
    E, nu, rho = 200e9, 0.3, 7850.0
    c_plate, c_bar = math.sqrt(E / (rho * (1 - nu * nu))), math.sqrt(E / rho)
    a, b, th = 0.010, 0.006, math.radians(45.0)
    p1, p2 = (0.0, 0.0), (a, 0.0)
    p4 = (b * math.cos(th), b * math.sin(th))
    p3 = (a + p4[0], p4[1])
    area_q = a * b * math.sin(th)
    d13, d24 = math.dist(p1, p3), math.dist(p2, p4)
    area_t = 0.5 * a * b * math.sin(th)
    side_t = [a, math.dist(p2, p4), b]
    expect = {("quad", 0): area_q / a / c_plate, ("quad", 1): area_q / max(d13, d24) / c_plate,
              ("quad", 2): max(b, area_q / a) / c_bar,
              ("tri", 0): 2 * area_t / max(side_t) / c_plate, ("tri", 1): 2 * area_t / max(side_t) / c_plate,
              ("tri", 2): min(side_t) / c_bar}

    def deck(shape, isdo):
        nodes = [p1, p2, p3, p4] if shape == "quad" else [p1, p2, p4]
        conn = "       1       1       1       2       3       4" if shape == "quad" else \
            "       1       1       1       2       3       3"
        lines = ["*KEYWORD", "*TITLE", f"one free shell, ISDO {isdo}", "*CONTROL_TERMINATION", "   1.0e-06         2",
                 "*CONTROL_TIMESTEP", f"         0       0.9{isdo:>10d}", "*DATABASE_GLSTAT", " 1.000e-09",
                 "*SECTION_SHELL", "         1         2       1.0         2", "     0.001     0.001     0.001     0.001",
                 "*MAT_ELASTIC", "         1      7850 2.000e+11       0.3", "*PART", "shell",
                 "         1         1         1", "*NODE"]
        lines += [f"{k + 1:8d}{x:16.9e}{y:16.9e}{0.0:16.9e}       0       0" for k, (x, y) in enumerate(nodes)]
        lines += ["*ELEMENT_SHELL", conn, "*END"]
        return "\n".join(lines) + "\n"

    for shape in ("quad", "tri"):
        for isdo in (0, 1, 2):
            p, out, _ = run_text(f"step_{shape}_{isdo}", deck(shape, isdo))
            if p.returncode != 0:
                record(f"shell step ISDO {isdo} {shape} runs", False, p.stderr[-300:])
                continue
            dt = glstat(out)["time_step"][0]
            want = 0.9 * expect[(shape, isdo)]
            log = open(os.path.join(out, "d3hsp")).read()
            record(f"shell step, ISDO {isdo}, {'parallelogram' if shape == 'quad' else 'triangle'}: first step "
                   f"{dt:.6e} s against 0.9 L/c = {want:.6e} (rel 1e-6), d3hsp names the rule",
                   abs(dt / want - 1) < roundoff(1e-6) and f"shell step length ISDO {isdo}" in log)
    # the triangles' stability at their step: a 40 x 4 mm strip of 20 x 2
    # squares split in triangles, 1 mm thick, clamped at x = 0, its free
    # edge struck at 1 m/s across the plate
    n, m, h = 20, 2, 0.002
    lines = ["*KEYWORD", "*TITLE", "a cantilever of triangles struck at its free edge", "*CONTROL_TERMINATION",
             "   1.0e-03", "*DATABASE_GLSTAT", " 1.000e-06", "*SECTION_SHELL", "         1         2       1.0         2",
             "     0.001     0.001     0.001     0.001", "*MAT_ELASTIC", "         1      7850 2.000e+11       0.3",
             "*PART", "strip", "         1         1         1", "*NODE"]
    nid = lambda i, j: 1 + i + (n + 1) * j
    for j in range(m + 1):
        for i in range(n + 1):
            lines.append(f"{nid(i, j):8d}{i * h:16.9e}{j * h:16.9e}{0.0:16.9e}       0       0")
    lines.append("*ELEMENT_SHELL")
    e = 0
    for j in range(m):
        for i in range(n):
            q = [nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1)]
            for t in ([q[0], q[1], q[2], q[2]], [q[0], q[2], q[3], q[3]]):
                e += 1
                lines.append(f"{e:8d}       1" + "".join(f"{v:8d}" for v in t))
    lines += ["*SET_NODE_LIST", "         1"] + [f"{nid(0, j):10d}" for j in range(m + 1)]
    lines += ["*SET_NODE_LIST", "         2"] + [f"{nid(n, j):10d}" for j in range(m + 1)]
    lines += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         1         1         1",
              "*INITIAL_VELOCITY", "         2", "       0.0       0.0       1.0", "*END"]
    p, out, _ = run_text("tri_strip", "\n".join(lines) + "\n")
    if p.returncode != 0:
        record("triangle strip runs", False, p.stderr[-300:])
        return
    g = glstat(out)
    ncyc = int(re.search(r"cycles \.+ +(\d+)", open(os.path.join(out, "d3hsp")).read()).group(1))
    worst = float(np.max(np.abs(g["energy_ratio"] - 1)))
    record(f"shell step: a cantilever of triangles struck at its free edge runs {ncyc} cycles at ISDO 0 "
           f"(at least 4000) with the energy ratio within 1e-3 of 1 ({worst:.1e})", ncyc >= 4000 and worst < 1e-3)


def test_element_mass():
    """*ELEMENT_MASS: a point mass on a node. A steel bar (10 hexahedra of
    10 mm, 10 x 10 mm section, E 200 GPa) clamped at one end carries 1 kg
    on its free end (0.25 kg on each of the end face's four nodes), set
    moving at 1 m/s along the bar. Its period against the spring-mass
    T = 2 pi sqrt((M + m/3) / (E A / L)) (the bar's own mass m = 0.0785 kg
    by Rayleigh's third; the error of that estimate is of order (m/M)^2,
    under 1e-3): within 1%, from the tip velocity's sign changes over 1.5
    ms. d3hsp names the masses and their total. On a rigid body's node the
    mass joins the body (its mass exactly, the energy kept); a point mass on
    a node no deck defines is refused naming the line, the field and the
    node. *CONSTRAINED_EXTRA_NODES_NODE joins a node (no element's, with a
    point mass) to a spinning rigid block: the body carries its mass and the
    node keeps its distance to the block."""
    E, rho, L, a, M = 200e9, 7850.0, 0.1, 0.01, 1.0
    n = 10
    lines = ["*KEYWORD", "*TITLE", "a bar carrying a point mass", "*CONTROL_TERMINATION", "   1.5e-03",
             "*DATABASE_NODOUT", " 2.000e-07", "*DATABASE_HISTORY_NODE", f"{4 * n + 1:10d}",
             "*SECTION_SOLID", "         1         1", "*MAT_ELASTIC", "         1      7850 2.000e+11       0.0",
             "*PART", "bar", "         1         1         1", "*NODE"]
    nid = lambda i, j, k: 1 + 4 * i + 2 * k + j
    for i in range(n + 1):
        for k in range(2):
            for j in range(2):
                lines.append(f"{nid(i, j, k):8d}{i * L / n:16.9e}{j * a:16.9e}{k * a:16.9e}       0       0")
    lines.append("*ELEMENT_SOLID")
    for i in range(n):
        c = [nid(i, 0, 0), nid(i + 1, 0, 0), nid(i + 1, 1, 0), nid(i, 1, 0),
             nid(i, 0, 1), nid(i + 1, 0, 1), nid(i + 1, 1, 1), nid(i, 1, 1)]
        lines.append(f"{i + 1:8d}       1" + "".join(f"{v:8d}" for v in c))
    tip = [nid(n, j, k) for k in range(2) for j in range(2)]
    lines.append("*ELEMENT_MASS")
    lines += [f"{900 + q:8d}{v:8d}{M / 4:16.6e}{0:8d}" for q, v in enumerate(tip)]
    lines += ["*SET_NODE_LIST", "         1"] + [f"{nid(0, j, k):10d}" for k in range(2) for j in range(2)]
    lines += ["*SET_NODE_LIST", "         2"] + [f"{v:10d}" for v in tip]
    lines += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         0         0         0",
              "*INITIAL_VELOCITY", "         2", "       1.0       0.0       0.0", "*END"]
    p, out, path = run_text("element_mass", "\n".join(lines) + "\n")
    if p.returncode != 0:
        record("element mass: the bar with a point mass runs", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        t = f["nodout/time"][:]
        vx = f["nodout/x_velocity"][:, 0]
    # sign changes of the tip velocity, interpolated: half periods apart
    cross = [t[i] - vx[i] * (t[i + 1] - t[i]) / (vx[i + 1] - vx[i]) for i in range(len(t) - 1)
             if vx[i] * vx[i + 1] < 0]
    T = 2 * float(np.mean(np.diff(cross))) if len(cross) > 2 else float("nan")
    m = rho * L * a * a
    T0 = 2 * math.pi * math.sqrt((M + m / 3) / (E * a * a / L))
    log = open(os.path.join(out, "d3hsp")).read()
    record(f"element mass: the bar's period with 1 kg at its tip {T * 1e3:.4f} ms against the spring-mass "
           f"{T0 * 1e3:.4f} ms (within 1%: {T / T0 - 1:+.1e}); d3hsp names 4 point masses of 1 kg in all",
           abs(T / T0 - 1) < 0.01 and "point masses (*ELEMENT_MASS) 4, total" in log)
    # on a rigid body's node the mass joins the body: the spinning rigid
    # block of the verification decks (7.85 kg) with 1 kg on its node 1
    with open(os.path.join(ROOT, "input_decks/verify/rigid_spin.k")) as f:
        text = f.read().replace("*END", "*ELEMENT_MASS\n     901       1     1.000e+00       0\n*END")
    p, rout, _ = run_text("rigid_spin_mass", text)
    ok = p.returncode == 0
    if ok:
        with h5py.File(os.path.join(rout, "thist.h5"), "r") as f:
            mb, ratio = float(f["matsum/mass"][0][0]), f["glstat/energy_ratio"][:]
        ok = abs(mb - 8.85) < 1e-9 and float(np.max(np.abs(ratio - 1))) < 1e-6
        detail = f"body mass {mb:.12g} kg, energy ratio within {float(np.max(np.abs(ratio - 1))):.1e} of 1"
    else:
        detail = p.stderr[-300:]
    record(f"element mass: 1 kg on a node of the spinning rigid block joins the body (7.85 -> 8.85 kg, 1e-9; "
           f"energy ratio within 1e-6): {detail}", ok)
    # *CONSTRAINED_EXTRA_NODES_NODE: a node of no element, 30 mm off the
    # spinning rigid block, carrying 1 kg, joined to the block: the body is
    # 8.85 kg, the node keeps its distance to the block's node 1 (a rigid
    # motion: 1e-9 relative over the spin) and the energy is kept
    text2 = text.replace("*END", "*NODE\n     999 1.300000000e-01 2.500000000e-02 2.500000000e-02       0       0\n"
                         "*CONSTRAINED_EXTRA_NODES_NODE\n         1       999\n*DATABASE_NODOUT\n 1.000e-04\n"
                         "*DATABASE_HISTORY_NODE\n         1       999\n*END").replace(
        "     901       1     1.000e+00       0", "     901     999     1.000e+00       0")
    p, xout, _ = run_text("rigid_spin_extra", text2)
    ok = p.returncode == 0
    if ok:
        with h5py.File(os.path.join(xout, "thist.h5"), "r") as f:
            mb, ratio = float(f["matsum/mass"][0][0]), f["glstat/energy_ratio"][:]
            xs = np.stack([f["nodout/" + c + "_coordinate"][:] for c in "xyz"], axis=-1)
        dist = np.linalg.norm(xs[:, 1, :] - xs[:, 0, :], axis=-1)
        spread = float(np.max(np.abs(dist / dist[0] - 1)))
        moved = float(np.max(np.linalg.norm(xs[:, 1, :] - xs[0, 1, :], axis=-1)))
        log = open(os.path.join(xout, "d3hsp")).read()
        ok = (abs(mb - 8.85) < 1e-9 and spread < 1e-9 and moved > 1e-3 and float(np.max(np.abs(ratio - 1))) < 1e-6
              and "extra nodes on rigid bodies 1" in log)
        detail = (f"body {mb:.12g} kg, distance to node 1 kept to {spread:.1e} while the node moved {moved * 1e3:.1f} mm, "
                  f"energy ratio within {float(np.max(np.abs(ratio - 1))):.1e}")
    else:
        detail = p.stderr[-300:]
    record(f"extra nodes: a 1 kg node joined to the spinning rigid block moves with it (8.85 kg; distance kept to "
           f"1e-9; energy to 1e-6; named in d3hsp): {detail}", ok)
    p, _, _ = run_text("rigid_spin_extra_bad", text2.replace("*CONSTRAINED_EXTRA_NODES_NODE\n         1       999",
                                                            "*CONSTRAINED_EXTRA_NODES_NODE\n         1      9999"))
    record("extra nodes: an undefined node is refused (exit 1) naming the line, NID and the node",
           p.returncode == 1 and "*CONSTRAINED_EXTRA_NODES_NODE field NID: node 9999 is not defined" in p.stderr,
           p.stderr[-300:])
    # *ELEMENT_MASS_NODE_SET: the same 1 kg as one card on the tip's node
    # set, shared equally: the four 0.25 kg point masses again, so the run
    # is the point masses' bitwise
    text = open(path).read()
    i0 = text.index("*ELEMENT_MASS\n")
    i1 = text.index("*SET_NODE_LIST")
    text_ns = text[:i0] + f"*ELEMENT_MASS_NODE_SET\n{900:8d}{2:8d}{M:16.6e}{0:8d}\n" + text[i1:]
    p, nout, _ = run_text("element_mass_node_set", text_ns)
    ok, msg = (False, p.stderr[-300:]) if p.returncode else same_histories(out, nout)
    record("element mass: *ELEMENT_MASS_NODE_SET shares 1 kg over the tip's 4 nodes: the point masses' run bitwise",
           ok, msg)
    # *ELEMENT_MASS_PART FINMASS: the bar (no tip mass) made twice its own
    # mass, shared as its own nodal masses are: matsum's mass is the
    # FINMASS and the clamped-free bar's period 4 L / c grows by sqrt(2)
    # (the same stiffness, twice the density): within 1%
    # (every node set moving at 1 m/s, the clamped ones held: the bar's
    # first mode rings; a lone tip node set moving alone rang at the mesh's
    # top frequency)
    text_b = (text[:i0] + text[i1:]).replace("*INITIAL_VELOCITY\n         2", "*INITIAL_VELOCITY\n         0").replace(
        "*DATABASE_NODOUT", "*DATABASE_MATSUM\n 1.000e-04\n*DATABASE_NODOUT")
    periods = {}
    for label, extra in (("bare", ""), ("part", f"*ELEMENT_MASS_PART\n{1:8d}{0.0:16.6e}{2 * rho * L * a * a:16.6e}\n")):
        p, bout, _ = run_text("element_mass_" + label, text_b.replace("*END", extra + "*END"))
        if p.returncode != 0:
            record(f"element mass: the bar ({label}) runs", False, p.stderr[-300:])
            return
        with h5py.File(os.path.join(bout, "thist.h5"), "r") as f:
            t, vx, mb = f["nodout/time"][:], f["nodout/x_velocity"][:, 0], float(f["matsum/mass"][0][0])
        cr = [t[i] - vx[i] * (t[i + 1] - t[i]) / (vx[i + 1] - vx[i]) for i in range(len(t) - 1) if vx[i] * vx[i + 1] < 0]
        periods[label] = (2 * float(np.mean(np.diff(cr))), mb)
    log = open(os.path.join(TMP, "element_mass_part", "d3hsp")).read()
    r = periods["part"][0] / periods["bare"][0]
    record(f"element mass: *ELEMENT_MASS_PART FINMASS doubles the bar's mass (matsum {periods['part'][1]:.6g} kg against "
           f"{2 * rho * L * a * a:.6g}, 1e-9) and its period grows {r:.4f} times (sqrt 2 = 1.4142, 1%); named in d3hsp",
           abs(periods["part"][1] / (2 * rho * L * a * a) - 1) < 1e-9 and abs(r / math.sqrt(2) - 1) < 0.01
           and "*ELEMENT_MASS_PART: part 1: mass" in log)
    p, _, _ = run_text("element_mass_bad", open(path).read().replace(f"{900:8d}{tip[0]:8d}", f"{900:8d}{99999:8d}"))
    record("element mass: a point mass on an undefined node is refused (exit 1) naming the line, NID and the node",
           p.returncode == 1 and "*ELEMENT_MASS 900 field NID: node 99999 is not defined" in p.stderr
           and "element_mass_bad.k:" in p.stderr, p.stderr[-300:])


def cantilever_deck(n=20, elform=2, g=10.0, t_ramp=0.245, t_rel=0.37, tend=0.56):
    """A 1 m steel cantilever of n beams (ELFORM 2: A 4e-4, ISS = ITT
    1.3333e-8, J 2.25e-8, a 20 mm square; ELFORM 1: a 20 x 20 mm rectangle
    TS1 x TT1), clamped at x = 0, its s axis along y (orientation node), its
    weight ramped over four first periods to g along z, held, then
    released at t_rel to ring freely."""
    L = ["*KEYWORD", "*TITLE", "a cantilever of beams under its weight, then released", "*CONTROL_TERMINATION",
         f"{tend:10.4g}", "*DATABASE_GLSTAT", " 1.000e-03", "*DATABASE_NODOUT", " 5.000e-04", "*DATABASE_HISTORY_NODE",
         f"{n + 1:10d}"]
    if elform == 2:
        L += ["*SECTION_BEAM", "         1         2       1.0         2         0",
              f"{4e-4:10.4g}{1.3333333e-8:10.4e}{1.3333333e-8:10.4e}{2.25e-8:10.4g}"]
    else:
        L += ["*SECTION_BEAM", "         1         1       1.0         2         0", f"{0.02:10.4g}{0.02:10.4g}{0.02:10.4g}{0.02:10.4g}"]
    L += ["*MAT_ELASTIC", "         1      7850     2e+11       0.3", "*PART", "beam", "         1         1         1",
          "*NODE"]
    for i in range(n + 1):
        L.append(f"{i + 1:8d}{i / n:16.9e}{0.0:16.9e}{0.0:16.9e}" + ("       7       7" if i == 0 else "       0       0"))
    L.append(f"{n + 2:8d}{0.0:16.9e}{1.0:16.9e}{0.0:16.9e}       7       7")
    L.append("*ELEMENT_BEAM")
    for i in range(n):
        L.append(f"{i + 1:8d}       1{i + 1:8d}{i + 2:8d}{n + 2:8d}")
    L += ["*DEFINE_CURVE", "        50", f"{0.0:20.8e}{0.0:20.8e}", f"{t_ramp:20.8e}{g:20.8e}", f"{t_rel:20.8e}{g:20.8e}",
          f"{t_rel + 1e-5:20.8e}{0.0:20.8e}", f"{10.0:20.8e}{0.0:20.8e}"]
    L += ["*LOAD_BODY_Z", "        50       1.0", "*END"]
    return "\n".join(L) + "\n"


def test_beams():
    """*ELEMENT_BEAM with *SECTION_BEAM ELFORM 2 (Belytschko-Schwer
    resultant) and ELFORM 1 (Hughes-Liu), issue 33. A 1 m steel cantilever of 20
    beams under its weight: the tip's mean deflection over the hold against
    Euler-Bernoulli's q L^4 / (8 E I) within 1%, and, released, its ringing
    at the first frequency 1.875^2/(2 pi) sqrt(E I / (rho A L^4)) within 1%
    (the lumped beam converges from below: 20 elements give -0.14%); the
    energy ratio within 1e-3 from 50 ms on. A 20 x 10 mm rectangle (ELFORM
    1) bends about its s axis (the orientation node's) with ISS = TS
    TT^3/12. The d3plot carries the beams and their resultants (VTK's
    reader reads them). A restart and two MPI ranks give the serial
    histories bitwise. ELFORM 1 is the Hughes-Liu beam (section points): a
    plastic cantilever collapses at its rule's limit load, a bar pulled
    past yield hardens as its law, a twisted one carries G J phi / L.
    A plastic ELFORM 2 beam and an orientation node on the axis are
    refused."""
    E, rho, L, g = 2e11, 7850.0, 1.0, 10.0
    cases = (("ELFORM 2, 20 mm square", cantilever_deck(elform=2), 4e-4, 1.3333333e-8),
             ("ELFORM 1, 20 x 10 mm rectangle", cantilever_deck(elform=1).replace(
                 f"{0.02:10.4g}{0.02:10.4g}{0.02:10.4g}{0.02:10.4g}", f"{0.02:10.4g}{0.02:10.4g}{0.01:10.4g}{0.01:10.4g}"),
              2e-4, 0.02 * 0.01 ** 3 / 12))
    for k, (label, text, A, I) in enumerate(cases):
        p, out, path = run_text(f"beam_cantilever_{k}", text)
        if p.returncode != 0:
            record(f"beams ({label}) run", False, p.stderr[-300:])
            return
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t, z = f["nodout/time"][:], f["nodout/z_displacement"][:, 0]
            # the ratio from 50 ms on (the ramp's first steps do little work,
            # and their ratio is the start's)
            ratio = f["glstat/energy_ratio"][:][f["glstat/time"][:] > 0.05]
        d = rho * A * g * L ** 4 / (8 * E * I)
        mean = -float(np.mean(z[(t > 0.245) & (t < 0.37)]))
        tt, zz = t[t > 0.38], z[t > 0.38]
        cr = [tt[i] - zz[i] * (tt[i + 1] - tt[i]) / (zz[i + 1] - zz[i]) for i in range(len(tt) - 1) if zz[i] * zz[i + 1] < 0]
        f1 = 1 / (2 * float(np.mean(np.diff(cr)))) if len(cr) > 2 else float("nan")
        f0 = 1.875 ** 2 / (2 * math.pi) * math.sqrt(E * I / (rho * A * L ** 4))
        dev = float(np.max(np.abs(ratio - 1)))
        record(f"beams ({label}): tip deflection {mean * 1e3:.4f} mm against q L^4/(8 E I) {d * 1e3:.4f} mm (1%: "
               f"{mean / d - 1:+.2%}); first frequency {f1:.3f} Hz against {f0:.3f} (1%: {f1 / f0 - 1:+.2%}); energy "
               f"ratio within 1e-3 ({dev:.1e})", abs(mean / d - 1) < 0.01 and abs(f1 / f0 - 1) < 0.01 and dev < 1e-3)
        if k == 0:
            first, first_path = out, path
    # the d3plot carries the beams: VTK's reader (an independent one) finds
    # the 20 beam cells in the part, with their ids, and the root element's
    # shear resultant at 0.3 s (the weight held since 0.245 s) is the weight
    # beyond its mid-length, rho A g (L - L/40), within 3% (what is left of
    # the ramp's ringing)
    try:
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy as v2n
    except ImportError:
        vtk = None
        skip("beams in the d3plot: VTK's LS-DYNA reader (Debian's python3-vtk9) is not installed")
    if vtk is not None:
        dout = os.path.join(TMP, "beam_d3plot")
        dpath = os.path.join(TMP, "beam_d3plot.k")
        with open(dpath, "w") as f:
            f.write(open(first_path).read().replace("*END", "*DATABASE_BINARY_D3PLOT\n      0.05\n*END"))
        q = run([XDYNA, "i=" + dpath, "outdir=" + dout, "endtim=0.3", "h5plot=1"])
        ok, detail = q.returncode == 0, q.stderr[-300:]
        if ok:
            r = vtk.vtkLSDynaReader()
            r.SetDatabaseDirectory(dout)
            r.UpdateInformation()
            r.SetTimeStep(r.GetNumberOfTimeSteps() - 1)
            r.Update()
            blocks = vtk_blocks(r)
            b = blocks[0][1] if blocks else None
            want = 7850 * 4e-4 * g * (1 - 1 / 40)
            if b is None or b.GetNumberOfCells() != 20:
                ok, detail = False, f"{len(blocks)} blocks, {b.GetNumberOfCells() if b else 0} cells"
            else:
                ids = v2n(b.GetCellData().GetArray("UserIds"))
                shear = v2n(b.GetCellData().GetArray("ShearResultant"))
                root = float(np.abs(shear[list(ids).index(1)]).max())
                ok = sorted(ids.tolist()) == list(range(1, 21)) and b.GetCellType(0) == vtk.VTK_LINE and \
                    abs(root / want - 1) < 0.03
                detail = f"root shear {root:.3f} N against {want:.3f} N ({root / want - 1:+.2%})"
        record(f"beams: VTK's LS-DYNA reader opens the cantilever's d3plot with its 20 beams (line cells, ids "
               f"1-20) and their resultants: {detail}", ok)
        # the same run's d3plot.h5 (h5plot=1) carries the beams too: their
        # connectivity and ids, and per state the six resultants, equal to
        # the binary d3plot's as VTK read them (both single precision from
        # the same values: exactly); the XDMF's beam block names a line
        # topology on beam_connectivity and its hyperslabs select columns
        # of beam_resultants that exist
        import xml.etree.ElementTree as ET
        hok, hdetail = False, "no d3plot.h5"
        h5p = os.path.join(dout, "d3plot.h5")
        if ok and os.path.exists(h5p):
            with h5py.File(h5p, "r") as f:
                last = sorted(k for k in f["states"] if k != "time")[-1]
                hid = f["mesh/beam_ids"][:]
                hconn = f["mesh/beam_connectivity"][:]
                hres = f[f"states/{last}/beam_resultants"][:]
                nnode = f["mesh/node_ids"].shape[0]
            vid = v2n(b.GetCellData().GetArray("UserIds")).tolist()
            vsh = v2n(b.GetCellData().GetArray("ShearResultant"))
            same = all(np.array_equal(hres[list(hid).index(i), 1:3], vsh[j]) for j, i in enumerate(vid))
            hroot = float(np.abs(hres[list(hid).index(1), 1:3]).max())
            root_x = ET.parse(os.path.join(dout, "d3plot.xdmf")).getroot()
            beams_grid = [g for g in root_x.iter("Grid") if g.get("Name") == "beams"]
            topo_ok = slabs_ok = False
            if beams_grid:
                tp = beams_grid[-1].find("Topology")
                topo_ok = (tp.get("TopologyType") == "Polyline" and tp.get("NodesPerElement") == "2"
                           and tp.find("DataItem").text.strip().endswith(":/mesh/beam_connectivity"))
                cols = []
                for at in beams_grid[-1].iter("Attribute"):
                    di = at.find("DataItem")
                    if di.get("ItemType") == "HyperSlab":
                        start = [int(v) for v in di.findall("DataItem")[0].text.split()]
                        cols.append(start[1])
                slabs_ok = sorted(cols) == list(range(6))
            hok = (sorted(hid.tolist()) == list(range(1, 21)) and hconn.shape == (20, 2) and hconn.min() >= 0
                   and hconn.max() < nnode and hres.shape == (20, 6) and same and abs(hroot / want - 1) < 0.03
                   and topo_ok and slabs_ok)
            hdetail = (f"root shear {hroot:.3f} N ({hroot / want - 1:+.2%}); the shears equal VTK's from the binary "
                       f"d3plot: {same}; XDMF line topology {topo_ok}, six resultant columns {slabs_ok}")
        record(f"beams: d3plot.h5 carries the 20 beams (ids, connectivity) and their six resultants per state, "
               f"the XDMF a beam block: {hdetail}", hok)
    # a plastic beam (ELFORM 1, *MAT_003 250 MPa, no hardening): its 2 x 2
    # Gauss points (QR 2, the default) all lie at |z| = h / (2 sqrt 3), so
    # the section yields at once at the rule's plastic moment M_r = sigma_y
    # A h / (2 sqrt 3) (15% above the exact b h^2 / 4, as the rule gives
    # it); the cantilever's weight ramped over 0.5 s to 1.2 times its
    # collapse load q_c = 2 M_r / L^2: the tip follows the elastic
    # deflection within 3% up to 0.95 q_c, and past q_c the root's hinge
    # lets it run away (at 1.2 q_c, 0.1 s on, more than twice the elastic
    # value); the plastic work is booked (energy ratio within 1e-3)
    gc = 2 * 250e6 * 4e-4 * 0.02 / (2 * math.sqrt(3)) / L ** 2 / (rho * 4e-4)
    text = cantilever_deck(elform=1, g=1.2 * gc, t_ramp=0.5, t_rel=5.0, tend=0.6).replace(
        "*MAT_ELASTIC\n         1      7850     2e+11       0.3",
        "*MAT_PLASTIC_KINEMATIC\n         1      7850     2e+11       0.3     2.5e8       0.0       1.0")
    p, out, _ = run_text("beam_plastic_collapse", text)
    if p.returncode != 0:
        record("beams: the plastic cantilever runs", False, p.stderr[-300:])
    else:
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t, z = f["nodout/time"][:], -f["nodout/z_displacement"][:, 0]
            ratio = f["glstat/energy_ratio"][:][f["glstat/time"][:] > 0.05]
        I = 0.02 ** 4 / 12

        def at(frac, tt=None):
            i = min(int(np.searchsorted(t, frac / 1.2 * 0.5 if tt is None else tt)), len(t) - 1)
            return z[i] / (rho * 4e-4 * gc * frac * L ** 4 / (8 * E * I))
        # (from 0.8 q_c: at 0.5 q_c, early in the ramp, the beam still lags
        # the load by 3%)
        below = max(abs(at(fr) - 1) for fr in (0.8, 0.9, 0.95))
        beyond = at(1.2, 0.6)
        dev = float(np.max(np.abs(ratio - 1)))
        record(f"beams: a plastic Hughes-Liu cantilever (ELFORM 1, *MAT_003, QR 2) is elastic below its collapse load "
               f"2 M_r/L^2 (within {below:.1%} of q L^4/8EI from 0.8 to 0.95 q_c; 3%) and runs away past it "
               f"({beyond:.2f} times the elastic deflection at 1.2 q_c; more than 2); energy ratio within 1e-3 "
               f"({dev:.1e})", below < 0.03 and beyond > 2 and dev < 1e-3)
    # hardening at the section points: a 6 mm Hughes-Liu bar (5 x 5 mm,
    # *MAT_003 SIGY 300 MPa, ETAN 2 GPa: E_p = E ETAN / (E - ETAN)) pulled
    # along its axis at 1 m/s, its ends otherwise held: past yield N = A
    # (SIGY + E_p eps_p), eps_p = ln(l/L) - N / (E A), within 1% at every
    # state; and torsion: a 0.1 m bar of 20 x 10 mm twisted at 1 rad/s
    # carries the elastic torque G J phi / L with J Saint-Venant's (a b^3
    # (1/3 - 0.21 b/a (1 - b^4/(12 a^4)))), within 1% (the section's points
    # alone would give the polar moment, 82% more)
    for case in ("axial", "torsion"):
        Lb, ts, tt, vel = (0.006, 0.005, 0.005, 1.0) if case == "axial" else (0.1, 0.02, 0.01, 1.0)
        mat = ("*MAT_PLASTIC_KINEMATIC\n         1      7850     2e+11       0.3     3e+08     2e+09       1.0"
               if case == "axial" else "*MAT_ELASTIC\n         1      7850     2e+11       0.3")
        # (the twist through a rigid plate of four shells about node 2, its
        # rotation about the bar's axis prescribed)
        rigid = [] if case == "axial" else (
            ["*SECTION_SHELL", "         2         2         1         2", "     0.001     0.001     0.001     0.001",
             "*MAT_RIGID", "         2      7850     2e+11       0.3", "*PART", "twister", "         2         2         2",
             "*NODE"] + [f"{4 + k:8d}{x:16.9e}{y:16.9e}{Lb:16.9e}       0       0" for k, (x, y) in enumerate(
                 [(-0.01, -0.01), (0.0, -0.01), (0.01, -0.01), (-0.01, 0.0), (0.01, 0.0), (-0.01, 0.01), (0.0, 0.01),
                  (0.01, 0.01)])] +
            ["*ELEMENT_SHELL", "       2       2       4       5       2       7", "       3       2       5       6       8       2",
             "       4       2       7       2      10       9", "       5       2       2       8      11      10",
             "*BOUNDARY_PRESCRIBED_MOTION_RIGID", f"         2         7         0         1{vel:10.4g}"])
        fix2 = "         2         0         1         1         0         1         1         1"
        deck = "\n".join([
            "*KEYWORD", "*TITLE", f"a Hughes-Liu bar ({case})", "*CONTROL_TERMINATION", " 4.000e-04",
            "*DATABASE_GLSTAT", " 1.000e-05", "*DATABASE_BINARY_D3PLOT", " 2.000e-05",
            "*SECTION_BEAM", "         1         1       1.0         2         0", f"{ts:10.4g}{ts:10.4g}{tt:10.4g}{tt:10.4g}",
            mat, "*PART", "bar", "         1         1         1", "*NODE",
            "       1             0.0             0.0             0.0       0       0",
            f"       2             0.0             0.0{Lb:16.9e}       0       0",
            "       3            0.01             0.0             0.0       0       0",
            "*ELEMENT_BEAM", "       1       1       1       2       3",
            "*BOUNDARY_SPC_NODE", "         1         0         1         1         1         1         1         1"] +
            ([fix2, "*BOUNDARY_PRESCRIBED_MOTION_NODE", f"         2         3         0         1{vel:10.4g}"]
             if case == "axial" else []) + rigid +
            ["*DEFINE_CURVE", "         1", "                 0.0                 1.0", "                 1.0                 1.0",
             "*END"]) + "\n"
        path = os.path.join(TMP, f"beam_hl_{case}.k")
        with open(path, "w") as f:
            f.write(deck)
        out = os.path.join(TMP, f"beam_hl_{case}")
        q = run([XDYNA, "i=" + path, "outdir=" + out, "h5plot=1"])
        if q.returncode != 0:
            record(f"beams: the Hughes-Liu bar ({case}) runs", False, q.stderr[-300:])
            continue
        with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
            keys = sorted(k for k in f["states"] if k != "time")
            tb = f["states/time"][:]
            R = np.array([f[f"states/{k}/beam_resultants"][0] for k in keys])
        sel = tb > 1e-5
        if case == "axial":
            A, Ep = ts * tt, E * 2e9 / (E - 2e9)
            want = A * (3e8 + Ep * np.log(1 + tb[sel] / Lb)) / (1 + Ep / E)
            err = float(np.max(np.abs(R[sel, 0] / want - 1)))
            record(f"beams: a Hughes-Liu bar (*MAT_003 ETAN 2 GPa) pulled past yield carries A (SIGY + E_p eps_p) "
                   f"at {int(sel.sum())} states (1%: largest {err:.2%}; {R[sel, 0][0] / 1e3:.2f} to "
                   f"{R[sel, 0][-1] / 1e3:.2f} kN)", sel.sum() > 10 and err < 0.01)
        else:
            a, b = ts, tt
            J = a * b ** 3 * (1 / 3 - 0.21 * (b / a) * (1 - b ** 4 / (12 * a ** 4)))
            want = E / 2.6 * J * tb[sel] / Lb
            err = float(np.max(np.abs(np.abs(R[sel, 5]) / want - 1)))
            record(f"beams: a Hughes-Liu bar of 20 x 10 mm twisted at 1 rad/s carries the torque G J phi / L with "
                   f"Saint-Venant's J at {int(sel.sum())} states (1%: largest {err:.2%})", sel.sum() > 10 and err < 0.01)
    rs = os.path.join(TMP, "beam_rs.k")
    with open(rs, "w") as f:
        f.write(open(first_path).read().replace("*END", "*DATABASE_BINARY_D3DUMP\n         0\n*END"))
    full, part = os.path.join(TMP, "beam_rs_full"), os.path.join(TMP, "beam_rs_part")
    q1 = run([XDYNA, "i=" + rs, "outdir=" + full, "endtim=0.3"])
    q2 = run([XDYNA, "i=" + rs, "outdir=" + part, "endtim=0.15"])
    q3 = run([XDYNA, "r=" + os.path.join(part, "d3dump.h5"), "endtim=0.3"])
    ok, msg = ((False, (q1.stderr + q2.stderr + q3.stderr)[-300:]) if q1.returncode or q2.returncode or q3.returncode
               else same_histories(full, part))
    record("beams: a restart from mid-ramp ends as the uninterrupted run (bitwise)", ok, msg)
    if shutil.which("mpirun") is not None:
        q = mpirun(2, ["i=" + first_path, "outdir=" + first + "_mpi2"])
        ok, msg = (False, q.stderr[-300:]) if q.returncode else ranks_match(first, first + "_mpi2")
        record("beams: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)", ok, msg)
    bad = open(first_path).read().replace("*MAT_ELASTIC\n         1      7850     2e+11       0.3",
                                          "*MAT_PLASTIC_KINEMATIC\n         1      7850     2e+11       0.3     3e+08")
    p, _, _ = run_text("beam_plastic", bad)
    record("beams: a plastic ELFORM 2 beam (no section dimensions for its plastic resultants) is refused (exit 1) "
           "naming the element and part",
           p.returncode == 1 and "*ELEMENT_BEAM 1 field PID: part 1: a plastic beam needs the section's dimensions"
           in p.stderr, p.stderr[-300:])
    bad = open(first_path).read().replace(f"{22:8d}{0.0:16.9e}{1.0:16.9e}", f"{22:8d}{2.0:16.9e}{0.0:16.9e}")
    p, _, _ = run_text("beam_axis_node", bad)
    record("beams: an orientation node on the beam's axis is refused (exit 1) naming it",
           p.returncode == 1 and "field N3: the orientation node 22 lies on the beam's axis" in p.stderr, p.stderr[-300:])


def test_shell_large_vibration():
    """An elastic clamped plate vibrating at large amplitude conserves its
    energy: ratio within 1e-3 over 200 us (about 7 periods, 590 cycles) at
    10, 30 and 100 m/s. Before the strain rates were taken on the mid-step
    geometry (they were taken on x(n) with v(n-1/2), which reads a rigid
    turn of theta per step as a membrane strain of order theta^2, always of
    one sign), the plate gained 2.4%, 22% and blew up at 100 m/s (stopped
    at 89 us with the energy ratio 1.5)."""
    for v in (10.0, 30.0, 100.0):
        deck = clamped_plate_deck(os.path.join(TMP, f"clamped_vib_{v:g}.k"), v)
        p, out = run_deck(deck, f"clamped_vib_{v:g}")
        if p.returncode != 0:
            record(f"clamped plate vibrating at {v:g} m/s runs", False, p.stderr[-300:])
            continue
        g = glstat(out)
        dev = np.max(abs(g["energy_ratio"] - 1))
        record(f"clamped plate vibrating at {v:g} m/s: energy kept to {dev:.1e} (within 1e-3) over "
               f"{g['time'][-1] * 1e6:.0f} us", dev < 1e-3 and g["time"][-1] > 1.99e-4)


def test_clamped_plate():
    """Clamped square plate under a small uniform pressure (*LOAD_SHELL_SET on
    a *SET_SHELL_LIST_GENERATE), ramped over about four periods and held: the
    centre settles, averaged over the hold, at 0.00126 q a^4 / D within 5%
    (the issue's figure; the average removes the residual vibration)."""
    p, out = run_deck("input_decks/verify/clamped_plate.k", "clamped_plate")
    record("deck clamped_plate runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    E, nu, th, a, q = 200e9, 0.3, 0.002, 0.2, 1000.0
    w = 0.00126 * q * a ** 4 / (E * th ** 3 / (12 * (1 - nu ** 2)))
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        t, z = f["nodout/time"][:], f["nodout/z_displacement"][:, 0]
    got = -z[t > 0.01].mean()
    record(f"clamped plate: centre deflection within 5% of plate theory ({(got / w - 1) * 100:+.2f}%)",
           abs(got / w - 1) < 0.05)
    g = glstat(out)
    ww = g["total_energy"][0] + g["external_work"]
    dev = np.max(abs(g["total_energy"] - ww)) / np.max(abs(ww))
    record(f"clamped plate: the pressure's work balances the energy ({dev:.1e})", dev < 0.01)


@pytest.mark.xdist_group("bar_impact")
def test_subsystems(bar_impact_run):
    """A deck mixing solids, shells and a rigid part runs; its log lists those
    subsystems as on and the others as off; a solids-only deck lists shells
    and rigid bodies as off."""
    p, out = run_deck("input_decks/verify/mixed_solid_shell_rigid.k", "mixed")
    record("deck mixed_solid_shell_rigid runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    log = open(os.path.join(out, "d3hsp")).read()
    want_on = ["solid elements ............ on", "shell elements ............ on", "rigid bodies .............. on"]
    want_off = ["contact ................... off", "rigid walls ............... off",
                "failure and erosion ....... off", "beam elements ............. off"]
    record("mixed deck: the log lists solids, shells and rigid bodies on, contact, walls, erosion and beams off",
           all(w in log for w in want_on + want_off))
    # Only the rigid block (3.925 kg) starts moving, at 2 m/s; it drags the
    # elastic block and the shell plate after it through shared nodes.
    g = glstat(out)
    dev = np.max(abs(g["energy_ratio"] - 1))
    # 5.1e-5 measured at TSSFAC 0.9 (1.5e-6 at 0.45, 1.1e-7 at 0.225: the
    # error falls as dt^4, a near-stability-limit effect of the rigid block
    # dragging the light elastic nodes, not bookkeeping); 1e-4 leaves 2x room
    record(f"mixed deck: energy ratio within 1e-4 ({dev:.1e})", dev < 1e-4)
    share = np.max(g["internal_energy"]) / g["total_energy"][0]
    # The deck must actually deform for the energy check to mean anything.
    record(f"mixed deck: the rigid block strains the block and plate (internal energy "
           f"reaches {share:.0%} of the initial energy, over 5%)", share > 0.05)
    # No external force acts: the momentum (the global velocity, mass-weighted)
    # stays at its initial value to round-off, across solid, shell and rigid nodes.
    vz = g["z_velocity"]
    drift = np.max(abs(vz - vz[0])) / abs(vz[0])
    record(f"mixed deck: momentum conserved across solids, shells and the rigid part ({drift:.1e})",
           drift < 1e-9 and abs(vz[0]) > 0.1)
    # The same deck at rest under gravity: the rigid block carries the lumped
    # mass the elastic block puts on their shared nodes, so the body and the
    # free nodes fall alike and nothing deforms. Before the body carried that
    # mass, the body fell faster than g and strained the block: internal
    # energy 1.5e-6 of the kinetic energy.
    p2, out2 = run_deck("input_decks/verify/mixed_solid_shell_rigid_gravity.k", "mixed_gravity")
    if p2.returncode == 0:
        g2 = glstat(out2)
        strain = np.max(g2["internal_energy"]) / g2["kinetic_energy"][-1]
        record(f"rigid part sharing nodes with solids falls with them under gravity: internal energy "
               f"{strain:.1e} of kinetic (tolerance 1e-12, round-off)", strain < 1e-12 and g2["kinetic_energy"][-1] > 0)
    else:
        record("mixed gravity deck runs", False, p2.stderr[-300:])
    record("*CONTROL_SHELL: MITER (not implemented) warned by name; WRPANG, THEORY 2 and ISTUPD not",
           "field MITER: not implemented" in log and "field WRPANG" not in log and "field THEORY" not in log
           and "field ISTUPD" not in log)
    log = open(os.path.join(bar_impact_run[1], "d3hsp")).read()
    record("solids-only deck: the log lists shells and rigid bodies off",
           "shell elements ............ off" in log and "rigid bodies .............. off" in log)


def thkchg_deck(path, thkchg, istupd=1):
    """Plate A (20 mm square, 10 x 10 shells, 1 mm, elastic steel) stretched
    in its plane by 20% over 1 ms, then held for 0.5 ms (every node's x and y
    velocity prescribed, proportional to its position; z held), thinning under *CONTROL_SHELL
    ISTUPD; plate B (8 mm, 4 x 4 shells, 1 mm) resting on it, 1 um above
    contact, pressed down by a body load of 1000 m/s^2. Single surface,
    SSTHK 1 (the shells' own thickness), THKCHG as given."""
    lines = ["*KEYWORD", "*TITLE", f"THKCHG {thkchg}: a plate resting on a thinning plate", "*CONTROL_TERMINATION",
             "  1.5e-3", "*CONTROL_SHELL", f"      20.0         0        -1{istupd:10d}",
             "*CONTROL_CONTACT", f"       0.1         0         0         0         0{thkchg:10d}",
             "         0         0         0         0         0         1",
             "*DATABASE_GLSTAT", "  1.0e-5", "*DATABASE_NODOUT", "  1.0e-5", "*DATABASE_HISTORY_NODE", "      1013",
             "*SECTION_SHELL", "         1         2         1         2", "     0.001     0.001     0.001     0.001",
             "*MAT_ELASTIC", "         1      7850 2.000e+11       0.3",
             "*PART", "plate A", "         1         1         1", "*PART", "plate B", "         2         1         1",
             "*DEFINE_CURVE", "         1", "                 0.0                 1.0", "                 1.0                 1.0",
             "*DEFINE_CURVE", "         2", "                 0.0                 1.0", "              1.0e-3                 1.0",
             "             1.01e-3                 0.0", "                 1.0                 0.0",
             "*LOAD_BODY_Z", "         1    1000.0", "*CONTACT_AUTOMATIC_SINGLE_SURFACE", "         0", "", "", "*NODE"]
    na, nb = 11, 5
    a = [(1 + i + na * j, -0.01 + 0.002 * i, -0.01 + 0.002 * j, 0.0) for j in range(na) for i in range(na)]
    b = [(1001 + i + nb * j, -0.004 + 0.002 * i, -0.004 + 0.002 * j, 1.0e-3 + 1.0e-6) for j in range(nb) for i in range(nb)]
    lines += [f"{n:8d}{x:16.8e}{y:16.8e}{z:16.8e}" for n, x, y, z in a + b]
    lines += ["*ELEMENT_SHELL"]
    e = 0
    for n, base, part in ((na, 1, 1), (nb, 1001, 2)):
        for j in range(n - 1):
            for i in range(n - 1):
                e += 1
                c = base + i + n * j
                lines.append(f"{e:8d}{part:8d}{c:8d}{c + 1:8d}{c + n + 1:8d}{c + n:8d}")
    # A: x, y velocity 200/s times the initial position (20% over 1 ms), z
    # and rotations held
    lines += node_set(1, [n for n, *_ in a])
    lines += ["*BOUNDARY_SPC_SET", "         1         0         0         0         1         1         1         1"]
    for n, x, y, _ in a:
        for dof, c in ((1, x), (2, y)):
            if c != 0.0:
                lines += ["*BOUNDARY_PRESCRIBED_MOTION_NODE", f"{n:10d}{dof:10d}         0         2{200.0 * c:10.4g}"]
            else:
                lines += ["*BOUNDARY_SPC_NODE", f"{n:10d}         0" + ("         1         0" if dof == 1 else
                                                                       "         0         1") + "         0"]
    lines.append("*END")
    return write_lines(path, lines)


def test_thkchg():
    """THKCHG of *CONTROL_CONTACT with *CONTROL_SHELL ISTUPD: plate B rests
    on plate A while A is stretched 20% in its plane and thins elastically,
    t = t0 (1.2)^(-2 nu / (1 - nu)) = 0.8553 mm, then held. With THKCHG 1
    B's centre ends (mean of the last 0.3 ms) at the contact distance of the
    thinned plate, (0.8553 + 1) / 2 = 0.9277 mm, within 4% of its 72.3 um
    descent (the spring's sag under B's weight is nanometres; the rest is
    B's vibration; measured 1.3%); with THKCHG 0 it stays at 1.000 mm
    within 1 um (the initial thickness); on 2 MPI ranks bitwise the serial
    run. THKCHG 1 with ISTUPD 0 is warned in d3hsp; THKCHG
    2 is refused naming the field."""
    zend = {}
    for tag in (0, 1):
        deck = thkchg_deck(os.path.join(TMP, f"thkchg{tag}.k"), tag)
        p, out = run_deck(deck, f"thkchg{tag}")
        if p.returncode != 0:
            record(f"THKCHG {tag}: the thinning plate deck runs", False, p.stderr[-300:])
            return
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            z = f["nodout/z_coordinate"][:, 0]
        zend[tag] = float(z[-30:].mean())   # the last 0.3 ms, A held
        if tag == 1:
            log = open(os.path.join(out, "d3hsp")).read()
            if shutil.which("mpirun"):
                # the thickness of other ranks' shells: the largest over the ranks
                mout = os.path.join(TMP, "thkchg1_mpi2")
                pm = mpirun(2, ["i=" + deck, "outdir=" + mout])
                ok, msg = (False, pm.stderr[-300:]) if pm.returncode else ranks_match(out, mout)
                record("THKCHG 1: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)", ok, msg)
    want = 0.5 * (1.0e-3 * 1.2 ** (-2 * 0.3 / 0.7) + 1.0e-3)
    drop = 1.0e-3 - want
    record(f"THKCHG 1: the plate resting on a thinning plate follows it down to {zend[1] * 1e3:.5f} mm "
           f"(contact distance of the thinned plate {want * 1e3:.5f} mm; error {abs(zend[1] - want) / drop:.1%} "
           f"of the {drop * 1e6:.1f} um descent, band 4%)", abs(zend[1] - want) <= 0.04 * drop)
    record(f"THKCHG 0: the same plate stays at the initial thickness's distance ({zend[0] * 1e3:.5f} mm, band 1 um "
           f"of 1 mm)", abs(zend[0] - 1.0e-3) <= 1.0e-6)
    record("THKCHG 1: d3hsp says the contact thickness follows the shells'", "THKCHG 1: the shell contact" in log)
    deck = thkchg_deck(os.path.join(TMP, "thkchg_noistupd.k"), 1, istupd=0)
    p, out = run_deck(deck, "thkchg_noistupd", extra=("endtim=1e-5",))
    record("THKCHG 1 with ISTUPD 0: warned in d3hsp (the thickness does not change)",
           p.returncode == 0 and "THKCHG 1: *CONTROL_SHELL ISTUPD is 0" in open(os.path.join(out, "d3hsp")).read())
    deck = write_lines(os.path.join(TMP, "thkchg2.k"),
                       open(thkchg_deck(os.path.join(TMP, "thkchg_b.k"), 1)).read().replace(
                           "         0         0         1\n", "         0         0         2\n", 1).splitlines())
    p = run([XDYNA, "i=" + deck, "outdir=" + os.path.join(TMP, "thkchg2")])
    record("THKCHG 2: refused (exit 1) naming the field and value",
           p.returncode == 1 and "THKCHG" in p.stderr and "2 is not 0" in p.stderr, p.stderr[-300:])


def ms_glstat(out):
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        g = f["glstat"]
        return {k: g[k][:] for k in g}


def test_mass_scaling():
    """Mass scaling (*CONTROL_TIMESTEP DT2MS, MS1ST; *CONTROL_TERMINATION
    ENDMAS), input_decks/verify/shell_pinch_mass_scaling.k: a 2 mm column of
    two shells pinched to 1 mm at 2 m/s between a held and a driven block,
    every node held in y and z, so its width w(t) = 2 mm - 2 m/s t and its
    step w/c (area over the longest side, plate wave speed c) are known.
    DT2MS -1e-6: the column's mass factor is (1e-6 c / w)^2, 7.00 at t = 0
    and 28.0 at the end; the run's step stays TSSFAC x 1e-6 = 0.9 us
    (rel 1e-9: the step is that product); the added mass at the end is
    2 m_e (f - 1) of the last cycle's width (band 0.5%: the element pass
    sees the width a cycle apart from the last output, 2 um of 1 mm, 0.4%
    in f); the kinetic energy the added mass entered with (d3hsp) is
    1/2 (2 m/s)^2 times the half of the mass added after cycle 0 that sits on
    the moving nodes (rel 1e-3); glstat's added mass and percentage and
    matsum's +mass read the same. Without DT2MS the step falls with the
    width (to 0.9 w_end / c within 1%). ENDMAS 50 stops the run (exit 2,
    naming ENDMAS and a node) within two steps of the time the added mass
    passes 50% of the model's. MS1ST 1 adds mass at cycle 0 only. DT2MS
    +1e-6 sets every element's mass at cycle 0 so that its step is 1e-6:
    the wide shells lose mass (factor (1e-6 c / 10 mm)^2), the total read
    from glstat at t = 0 (rel 1e-6). Stability: the right block thrown at
    the column at 2 m/s instead of driven (its kinetic energy goes into the
    column's strain and back) runs 2,000 steps of at least 0.9 us, 2.6 times
    the unscaled column's stable step, with the energy ratio within 1e-3
    (without the added mass it would blow up in a few steps). A
    hexahedron bar with one 2 mm element likewise: step TSSFAC |DT2MS| and
    added mass m_e ((|DT2MS| / dt_e)^2 - 1), dt_e the run's first step
    without DT2MS over TSSFAC (rel 1e-6). On 2 MPI ranks the pinch's
    histories are the serial ones bitwise."""
    src = "input_decks/verify/shell_pinch_mass_scaling.k"
    text = open(os.path.join(ROOT, src)).read()
    rho, E, nu, h = 7850.0, 2.0e11, 0.3, 1.0e-3
    c = math.sqrt(E / (rho * (1 - nu * nu)))
    me = rho * h * 2.0e-3 * 1.0e-2           # a column shell's own mass
    base = rho * h * (0.042 * 0.02)          # the strip's
    variant = lambda name, t: write_lines(os.path.join(TMP, name + ".k"), t.splitlines())
    dt2ms_card = "       0.0       0.9         0       0.0   -1.0e-6"

    p, out = run_deck(src, "ms_pinch")
    if p.returncode:
        record("mass scaling: the pinch deck runs", False, p.stderr[-300:])
        return
    gl = ms_glstat(out)
    log = open(os.path.join(out, "d3hsp")).read()
    step = gl["time_step"]
    record(f"mass scaling: the step stays TSSFAC x |DT2MS| = 0.9 us ({step.min():.6e} to {step.max():.6e} s, rel 1e-9)",
           abs(step.min() - 0.9e-6) <= 0.9e-15 and abs(step.max() - 0.9e-6) <= 0.9e-15)
    f0 = (1.0e-6 * c / 2.0e-3) ** 2
    named = re.findall(r"mass scaling: shell (\d+) of part 1 at time \S+, cycle 0: its mass x (\S+)", log)
    record(f"mass scaling: d3hsp names shells 3 and 8 at cycle 0, factor {[float(x) for _, x in named]} against "
           f"(1e-6 c / 2 mm)^2 = {f0:.5f} (rel 1e-4)",
           sorted(int(e) for e, _ in named) == [3, 8] and all(abs(float(x) / f0 - 1) <= 1e-4 for _, x in named))
    t_end = float(gl["time"][-1])
    w_end = 2.0e-3 - 2.0 * t_end
    f_end = (1.0e-6 * c / w_end) ** 2
    want = 2 * me * (f_end - 1)
    got = float(gl["added_mass"][-1])
    record(f"mass scaling: added mass at the end {got:.5e} against 2 m_e (f - 1) = {want:.5e} for the width "
           f"{w_end * 1e3:.4f} mm (error {got / want - 1:+.2e}, band 0.5%)", abs(got / want - 1) <= 5e-3)
    m = re.search(r"kinetic energy the added mass entered with: (\S+)", log)
    ke_want = 0.5 * 2.0 ** 2 * 0.5 * (got - 2 * me * (f0 - 1))
    record(f"mass scaling: the added mass's kinetic energy {m.group(1) if m else None} against 1/2 v^2 dm_moving = "
           f"{ke_want:.5e} (rel 1e-3)", m is not None and abs(float(m.group(1)) / ke_want - 1) <= 1e-3)
    txt = open(os.path.join(out, "glstat")).read()
    am = re.findall(r" added mass\.+\s+(\S+)", txt)
    pc = re.findall(r" percentage increase\.+\s+(\S+)", txt)
    ms = re.findall(r"\+mass=\s*(\S+)", open(os.path.join(out, "matsum")).read())
    record(f"mass scaling: glstat's added mass {am[-1] if am else None} and percentage {pc[-1] if pc else None}, "
           f"matsum's +mass {ms[-1] if ms else None} agree with thist.h5 (5 digits)",
           bool(am and pc and ms) and abs(float(am[-1]) / got - 1) < 1e-4 and abs(float(ms[-1]) / got - 1) < 1e-4
           and abs(float(pc[-1]) / (100 * got / base) - 1) < 1e-4)
    ratio = gl["energy_ratio"]
    record(f"mass scaling: the energy ratio (the added mass's kinetic energy counted as put in) within 2e-3 of 1 "
           f"(worst {abs(ratio - 1).max():.2e}; the unscaled run's large-strain error is of that order)",
           abs(ratio - 1).max() <= 2e-3)

    m = re.search(r"time step over the (\d+) cycles of this run: set by an element in (\d+) cycles.*mass-scaling "
                  r"floor TSSFAC x \|DT2MS\| in (\d+) cycles", log)
    record(f"step control in d3hsp: the DT2MS floor set the step in every cycle ({m.groups() if m else None})",
           m is not None and m.group(1) == m.group(3) and int(m.group(1)) > 500 and m.group(2) == "0")
    p, out0 = run_deck(variant("ms_pinch_off", text.replace(dt2ms_card, "       0.0       0.9")), "ms_pinch_off")
    g0 = ms_glstat(out0) if p.returncode == 0 else None
    log0 = open(os.path.join(out0, "d3hsp")).read() if p.returncode == 0 else ""
    m = re.search(r"time step over the (\d+) cycles of this run: set by an element in (\d+) cycles.*\n   shell (\d+) of "
                  r"part 1: (\d+) cycles", log0)
    record(f"step control in d3hsp without DT2MS: an element in every cycle, the column's shell 3 or 8 most often "
           f"({m.groups() if m else None})", m is not None and m.group(1) == m.group(2) and m.group(3) in ("3", "8"))
    record(f"mass scaling: without DT2MS the step falls with the width "
           f"({g0['time_step'].min() if g0 else 0:.4e} s against 0.9 w_end / c = {0.9 * w_end / c:.4e}, band 1%)",
           g0 is not None and abs(g0["time_step"].min() / (0.9 * w_end / c) - 1) <= 0.01, p.stderr[-300:])

    t_half = (2.0e-3 - 1.0e-6 * c / math.sqrt(1 + 0.5 * base / (2 * me))) / 2.0
    deck = variant("ms_pinch_endmas", text.replace("*CONTROL_TERMINATION\n    5.0e-4",
                                                   "*CONTROL_TERMINATION\n    5.0e-4         0       0.0       0.0      50.0"))
    p, oute = run_deck(deck, "ms_pinch_endmas")
    m = re.search(r"error termination at time (\S+),", p.stdout + p.stderr)
    t_stop = float(m.group(1)) if m else -1
    record(f"mass scaling: ENDMAS 50 stops the run (exit {p.returncode}) at {t_stop:.4e} s, where the added mass "
           f"passes 50% at {t_half:.4e} s (band two steps), naming ENDMAS and a node",
           p.returncode == 2 and abs(t_stop - t_half) <= 1.8e-6 and "ENDMAS" in p.stderr and "at node" in p.stderr,
           (p.stderr)[-300:])

    p, out1 = run_deck(variant("ms_pinch_ms1st", text.replace(dt2ms_card, dt2ms_card + "         0         0         1")),
                       "ms_pinch_ms1st")
    g1 = ms_glstat(out1) if p.returncode == 0 else None
    record("mass scaling: MS1ST 1 scales at cycle 0 only (the added mass stays 2 m_e (f0 - 1), rel 1e-9, and the "
           "step then falls below 0.9 us)", g1 is not None and np.all(abs(g1["added_mass"] / (2 * me * (f0 - 1)) - 1)
                                                               <= 1e-9) and g1["time_step"].min() < 0.85e-6,
           p.stderr[-300:])

    # the right block thrown at the column instead of driven
    free = text.replace("*BOUNDARY_PRESCRIBED_MOTION_SET\n         3         1         0         1       1.0",
                        "*INITIAL_VELOCITY\n         3\n      -2.0       0.0       0.0")
    free = free.replace("*CONTROL_TERMINATION\n    5.0e-4", "*CONTROL_TERMINATION\n    1.8e-3")
    p, outf = run_deck(variant("ms_pinch_free", free), "ms_pinch_free")
    gf = ms_glstat(outf) if p.returncode == 0 else None
    ok = gf is not None and len(gf["time_step"]) > 100
    record(f"mass scaling: the block thrown at the column runs to 1.8 ms in steps of at least 0.9 us "
           f"({0.9e-6 / (0.9 * 2.0e-3 / c):.2f} x the unscaled column's step) with the energy ratio within 1e-3 "
           f"(worst {abs(gf['energy_ratio'] - 1).max() if ok else float('nan'):.2e})",
           ok and abs(gf["energy_ratio"] - 1).max() <= 1e-3 and gf["time_step"].min() >= 0.9e-6 * (1 - 1e-9)
           and gf["time"][-1] >= 1.8e-3 * (1 - 1e-6) and gf["internal_energy"].max() > 0.5 * gf["kinetic_energy"][0],
           p.stderr[-300:])

    pos = free.replace(dt2ms_card, "       0.0       0.9         0       0.0    1.0e-6").replace(
        "*CONTROL_TERMINATION\n    1.8e-3", "*CONTROL_TERMINATION\n    1.0e-5")
    p, outp = run_deck(variant("ms_pinch_positive", pos), "ms_pinch_positive")
    gp = ms_glstat(outp) if p.returncode == 0 else None
    fw = (1.0e-6 * c / 1.0e-2) ** 2
    want = 2 * me * (f0 - 1) + 8 * (rho * h * 1.0e-4) * (fw - 1)
    record(f"mass scaling: DT2MS +1e-6 sets every shell's mass at cycle 0 (added {gp['added_mass'][0] if gp else 0:.6e} "
           f"against {want:.6e}: the wide shells x {fw:.4f}, the column x {f0:.4f}; rel 1e-6)",
           gp is not None and abs(gp["added_mass"][0] / want - 1) <= 1e-6, p.stderr[-300:])

    # a hexahedron bar with one 2 mm element
    hx = ["*KEYWORD", "*TITLE", "mass scaling of a thin hexahedron", "*CONTROL_TERMINATION", "    2.0e-5",
          "*CONTROL_TIMESTEP", "DT2MS", "*DATABASE_GLSTAT", "    1.0e-6", "*SECTION_SOLID", "         1         1",
          "*MAT_ELASTIC", "         1      7850 2.000e+11       0.3", "*PART", "bar", "         1         1         1",
          "*INITIAL_VELOCITY", "         0", "       1.0       0.0       0.0", "*NODE"]
    xs = [0.0, 0.01, 0.012, 0.022]
    nid = lambda i, j, k: 1 + i + 4 * (j + 2 * k)
    hx += [f"{nid(i, j, k):8d}{x:16.8e}{0.01 * j:16.8e}{0.01 * k:16.8e}" for k in range(2) for j in range(2)
           for i, x in enumerate(xs)]
    hx += ["*ELEMENT_SOLID"] + [f"{i + 1:8d}{1:8d}" + "".join(f"{n:8d}" for n in (
        nid(i, 0, 0), nid(i + 1, 0, 0), nid(i + 1, 1, 0), nid(i, 1, 0), nid(i, 0, 1), nid(i + 1, 0, 1), nid(i + 1, 1, 1),
        nid(i, 1, 1))) for i in range(3)] + ["*END"]
    steps = {}
    for tag, card in (("off", "       0.0       0.9"), ("on", "       0.0       0.9         0       0.0   -1.5e-6")):
        p, o = run_deck(variant("ms_hex_" + tag, "\n".join(hx).replace("DT2MS", card)), "ms_hex_" + tag)
        steps[tag] = ms_glstat(o) if p.returncode == 0 else None
    ok = all(v is not None for v in steps.values())
    if ok:
        dte = steps["off"]["time_step"][0] / 0.9
        want = rho * 2.0e-3 * 1.0e-4 * ((1.5e-6 / dte) ** 2 - 1)
        got = steps["on"]["added_mass"][0]
        record(f"mass scaling: the thin hexahedron (step {dte:.4e} s unscaled) gets {got:.6e} kg against "
               f"m_e ((1.5 us / dt_e)^2 - 1) = {want:.6e} (rel 1e-6; the 10 mm cubes' 1.7 us steps keep their "
               f"mass) and the run's step at least 1.35 us (rel 1e-9) and at most 6.2% above (the linear bulk "
               f"viscosity's share of the step, sqrt(1 + Q2^2) + Q2 with Q2 0.06, taken when a round-off "
               f"volume rate is negative and left when it is not)",
               abs(got / want - 1) <= 1e-6 and steps["on"]["time_step"].max() <= 1.35e-6 * (math.hypot(1, 0.06) + 0.06)
               * (1 + 1e-9) and abs(steps["on"]["time_step"].min() / 1.35e-6 - 1) <= 1e-9)
    else:
        record("mass scaling: the thin hexahedron decks run", False)

    if shutil.which("mpirun"):
        mout = os.path.join(TMP, "ms_pinch_mpi2")
        pm = mpirun(2, ["i=" + os.path.join(ROOT, src), "outdir=" + mout])
        ok, msg = (False, pm.stderr[-300:]) if pm.returncode else ranks_match(out, mout)
        record("mass scaling: mpirun -np 2 gives the pinch's serial histories (bitwise; owned nodes: the motion)", ok, msg)


def test_lone_cube():
    """A lone free hexahedron (10 mm steel cube, nu 0.3) translating at (1, 2,
    3) m/s at TSSFAC 0.9 (issue 30, finding 10: it blew up at cycle 31).
    Its breathing mode allows sqrt((lambda + 2 mu) / 3K) = 0.734 of L/c;
    the set-up check finds it and scales the step to 0.98 of that (named in
    d3hsp, within 1%: the power iteration's convergence). The run ends
    normally, the translation unchanged to round-off (1e-9 of the speed:
    float sums over 8 nodes and 100 cycles), the energy ratio 1 within
    1e-6. At TSSFAC 0.6 the step is within the limit and nothing is
    scaled."""
    nu = 0.3
    lam_2mu = (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    three_k = 1 / (1 - 2 * nu)
    expect = 0.98 * np.sqrt(lam_2mu / three_k)
    p, out = run_deck("input_decks/verify/lone_cube.k", "lone_cube")
    log = open(os.path.join(out, "d3hsp")).read() if os.path.exists(os.path.join(out, "d3hsp")) else ""
    m = re.search(r"steps are scaled by\s+([0-9.]+)", log)
    got = float(m.group(1)) if m else 0.0
    record(f"lone cube: the set-up check scales its step by {got:.3f}, 0.98 of its breathing mode's "
           f"limit {expect:.3f} (1%)", p.returncode == 0 and abs(got / expect - 1) < 0.01, p.stdout[-300:])
    if p.returncode == 0:
        g = glstat(out)
        v = np.array([g["x_velocity"], g["y_velocity"], g["z_velocity"]]).T
        dev = float(np.max(np.abs(v - [1.0, 2.0, 3.0])))
        rdev = float(np.max(np.abs(g["energy_ratio"] - 1)))
        record(f"lone cube: the translation stays (1, 2, 3) m/s (largest deviation {dev:.1e} m/s), energy "
               f"ratio 1 ({rdev:.1e})", dev < 1e-9 * np.sqrt(14) and rdev < 1e-6)
    deck = os.path.join(TMP, "lone_cube_06.k")
    with open(deck, "w") as f:
        f.write(open(os.path.join(ROOT, "input_decks/verify/lone_cube.k")).read().replace(
            "         0       0.9", "         0       0.6"))
    q = run([XDYNA, "i=" + deck, "outdir=" + os.path.join(TMP, "lone_cube_06")])
    log = open(os.path.join(TMP, "lone_cube_06", "d3hsp")).read() if q.returncode == 0 else ""
    record("lone cube at TSSFAC 0.6: within the limit, runs with no step scaled", q.returncode == 0
           and "steps are scaled" not in log, q.stdout[-300:])
