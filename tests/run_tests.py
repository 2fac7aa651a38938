#!/usr/bin/python3
"""xdyna's test runner: unit tests, deck tests with physics answers, input
error tests, thdiff and command-line tests. Ends with 'N passed, N failed'.

Every check states its tolerance and why; see the comments at each test.
Run from the repository root after `make all tests` (`make check` does both).
"""
import glob
import math
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# XDYNA_BIN: another build to run the deck tests with (make PRECISION=single verify)
XDYNA = os.environ.get("XDYNA_BIN") or os.path.join(ROOT, "bin", "xdyna")
# A 32-bit build (make PRECISION=single: field data in 32 bits, energies and
# time in 64) rounds each operation to 2^-24 = 6e-8 relative; over the
# thousands of cycles of a test that grows to 1e-7..1e-6. A check whose
# tolerance bounds round-off (stated for 64 bits: 1e-9 and below) takes
# roundoff(tol, scale) = max(tol, 1e-5 x scale) there (scale: the size of
# the quantity, 1 for a ratio); checks of physics keep their tolerances.
SINGLE = os.path.basename(XDYNA).endswith("_single")


def roundoff(tol, scale=1.0):
    return max(tol, 1e-5 * scale) if SINGLE else tol

# The deck tests read the states from d3plot.h5 (h5py): every run here writes
# it beside the d3plot family (xdyna's default writes the family alone;
# test_d3plot checks that default with XDYNA_H5PLOT=0)
os.environ.setdefault("XDYNA_H5PLOT", "1")

THDIFF = os.path.join(ROOT, "bin", "thdiff")
TMP = tempfile.mkdtemp(prefix="xdyna-tests-")
results = []


def record(name, ok, detail=""):
    results.append((name, ok))
    print(("PASS " if ok else "FAIL ") + name + ("" if ok or not detail else ": " + detail), flush=True)


def run(args, cwd=None, env=None):
    e = dict(os.environ)
    e.setdefault("OMP_NUM_THREADS", "1")
    if env:
        e.update(env)
    return subprocess.run(args, cwd=cwd or ROOT, env=e, capture_output=True, text=True)


def run_deck(deck, name, env=None, extra=()):
    out = os.path.join(TMP, name)
    shutil.rmtree(out, ignore_errors=True)
    p = run([XDYNA, "i=" + os.path.join(ROOT, deck), "outdir=" + out, *extra], env=env)
    return p, out


def run_text(name, text):
    """Write a deck made here (`text`) as TMP/name.k and run it into
    TMP/name; returns the process, the output directory and the deck."""
    path = os.path.join(TMP, name + ".k")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(TMP, name)
    shutil.rmtree(out, ignore_errors=True)
    return run([XDYNA, "i=" + path, "outdir=" + out]), out, path


def glstat(out):
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        return {k: f["glstat"][k][:] for k in f["glstat"]}


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


def unit_tests():
    for exe in sorted(glob.glob(os.path.join(ROOT, "build", "tests", "test_*"))):
        p = run([exe])
        lines = [l for l in p.stdout.splitlines() if l.startswith(("PASS ", "FAIL "))]
        for l in lines:
            record("unit/" + os.path.basename(exe)[5:] + ": " + l[5:].split(": ")[0], l.startswith("PASS"),
                   l[5:])
        if p.returncode != 0 or not lines:
            record("unit/" + os.path.basename(exe) + " ran to the end", False, p.stderr[-400:])


def test_bar_impact():
    """(a) Elastic bar (nu = 0), moving at v0 and stopped at x = 0: the front
    runs at c = sqrt(E/rho) and carries sigma = rho c v0. Tolerance 2% (the
    issue's): the front is smeared over a few elements by bulk viscosity, and
    arrival is taken where the velocity has dropped by half."""
    p, out = run_deck("input_decks/verify/bar_impact.k", "bar_impact")
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


def test_bar_wall():
    """Elastic bar (nu = 0) at v0 onto a planar rigid wall (1-D theory):
    contact lasts 2L/c (2%), the wall force plateau is rho c A v0 (5%), the
    bar leaves at v0 (2%): the issue's tolerances. Energy, with the
    stonewall's share, within 2%."""
    p, out = run_deck("input_decks/verify/bar_wall.k", "bar_wall")
    record("deck bar_wall runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    E, rho, v0, A, L = 200e9, 7850.0, 10.0, 25e-6, 1.0
    c = np.sqrt(E / rho)
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        t = f["rwforc/time"][:]
        fn = f["rwforc/normal_force"][:, 0]
        fxw = f["rwforc/x_force"][:, 0]
        ids = f["rwforc/ids"][:]
    # LS-DYNA's rwforc gives the force of the wall on the structure: the bar
    # runs in -x into a wall whose normal is +x, so x_force is +normal_force
    # (1e-6 of the peak: the two are the same sums, only the projection's
    # round-off between them). It failed before: x_force was the force of the
    # nodes on the wall, -normal_force.
    record(f"bar on wall: rwforc x_force is the wall's push on the bar, +x, equal to the normal force "
           f"(peak {fxw.max():.4e} N)", fxw.max() > 0 and np.max(abs(fxw - fn)) <= 1e-6 * abs(fn).max())
    on = np.where(fn > 0)[0]
    dur = t[on[-1]] - t[on[0]]
    record(f"bar on wall: contact duration within 2% of 2L/c ({(dur / (2 * L / c) - 1) * 100:+.2f}%)",
           abs(dur / (2 * L / c) - 1) < 0.02)
    mid = (t > t[on[0]] + 0.1 * dur) & (t < t[on[-1]] - 0.1 * dur)
    plateau = fn[mid].mean()
    record(f"bar on wall: force plateau within 5% of rho c A v0 ({(plateau / (rho * c * A * v0) - 1) * 100:+.2f}%)",
           abs(plateau / (rho * c * A * v0) - 1) < 0.05)
    g = glstat(out)
    vx = g["x_velocity"][-1]
    record(f"bar on wall: rebound velocity within 2% of v0 ({(vx / v0 - 1) * 100:+.2f}%)", abs(vx / v0 - 1) < 0.02)
    dev = np.max(abs(g["energy_ratio"] - 1))
    record(f"bar on wall: energy ratio within 2% with the stonewall energy ({dev:.1e})", dev < 0.02)
    record("bar on wall: rwforc names the wall by its _ID", list(ids) == [7])
    # rtol 1e-3 of the peak: the ASCII file prints times with 6 digits, and
    # where the force falls steeply (the release) interpolating the HDF5
    # series at those rounded times moves it by about 2e-4 of the peak
    q = run([THDIFF, os.path.join(out, "rwforc"), os.path.join(out, "thist.h5"), "--common", "--only", "rwforc",
             "--rtol", "1e-3", "--atol", "1e-6"])
    record("bar on wall: ASCII rwforc and thist.h5 agree", q.returncode == 0, q.stdout[-300:])


def test_moving_walls():
    """*RIGIDWALL_PLANAR_MOVING: a wall 1000 times the bar's mass acts as the
    fixed wall (2L/c within 2%, rho c A v0 within 5%); a wall of the bar's
    mass is pushed away: the bar's momentum change equals the wall-force
    impulse (1%: sampled at the output interval) and the energy ratio counts
    the wall's kinetic energy (2%). *RIGIDWALL_GEOMETRIC_CYLINDER: a bar
    striking a pole ends with no node inside it (to rounding) and bounces."""
    E, rho, v0, A, L = 200e9, 7850.0, 10.0, 25e-6, 1.0
    c = np.sqrt(E / rho)
    for d in ("bar_heavy_wall", "bar_light_wall"):
        p, out = run_deck(f"input_decks/verify/{d}.k", d)
        record(f"deck {d} runs (exit 0)", p.returncode == 0, p.stderr[-300:])
        if p.returncode != 0:
            return
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t, fn = f["rwforc/time"][:], f["rwforc/normal_force"][:, 0]
        g = glstat(out)
        dev = np.max(abs(g["energy_ratio"] - 1))
        record(f"{d}: energy ratio within 2%, the wall's kinetic energy counted ({dev:.1e})", dev < 0.02)
        if d == "bar_heavy_wall":
            on = np.where(fn > 0)[0]
            dur = t[on[-1]] - t[on[0]]
            mid = (t > t[on[0]] + 0.1 * dur) & (t < t[on[-1]] - 0.1 * dur)
            record(f"heavy moving wall: contact 2L/c within 2% ({(dur / (2 * L / c) - 1) * 100:+.2f}%)",
                   abs(dur / (2 * L / c) - 1) < 0.02)
            record(f"heavy moving wall: plateau rho c A v0 within 5% "
                   f"({(fn[mid].mean() / (rho * c * A * v0) - 1) * 100:+.2f}%)",
                   abs(fn[mid].mean() / (rho * c * A * v0) - 1) < 0.05)
        else:
            impulse = np.trapz(fn, t)
            dmom = rho * L * A * (g["x_velocity"][-1] + v0)
            record(f"light moving wall: bar momentum change = wall impulse ({(dmom / impulse - 1) * 100:+.2f}%)",
                   abs(dmom / impulse - 1) < 0.01)
            record("light moving wall: the bar keeps moving after it (the wall was pushed)", g["x_velocity"][-1] < 0)
    p, out = run_deck("input_decks/verify/bar_on_pole.k", "bar_on_pole")
    record("deck bar_on_pole runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode == 0:
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            dist = np.hypot(f["nodout/x_coordinate"][:], f["nodout/y_coordinate"][:])
        record(f"pole: no node ends inside the cylinder (closest {dist.min():.9f} m, radius 0.01 m)",
               dist.min() > 0.01 * (1 - roundoff(1e-9)))
        g = glstat(out)
        record("pole: the bar bounces off", g["y_velocity"][-1] > 0)
        dev = np.max(abs(g["energy_ratio"] - 1))
        record(f"pole: energy ratio within 2% ({dev:.1e})", dev < 0.02)


def test_gravity_drop():
    """A block falls from rest under *LOAD_BODY_Z (a *DEFINE_CURVE of 9.81)
    onto a planar rigid wall: it arrives at sqrt(2 g h) within 0.5% (the
    issue's figure); energy ratio with the external work within 2%."""
    p, out = run_deck("input_decks/verify/gravity_drop.k", "gravity_drop")
    record("deck gravity_drop runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        vz = f["nodout/z_velocity"][:, 0]
        fzw = f["rwforc/z_force"][:, 0]
    # the ground (normal +z) pushes the block up: z_force is never negative
    # beyond round-off (1e-9 of its peak) and positive at the impact
    record(f"gravity drop: the ground's rwforc z_force is its upward push (peak {fzw.max():.4e} N, "
           f"least {fzw.min():.2e} N)", fzw.max() > 0 and fzw.min() >= -1e-9 * fzw.max())
    v_theory = -np.sqrt(2 * 9.81 * 0.5)
    err = vz.min() / v_theory - 1
    record(f"gravity drop: impact velocity within 0.5% of sqrt(2 g h) ({err * 100:+.3f}%)", abs(err) < 0.005)
    g = glstat(out)
    dev = np.max(abs(g["energy_ratio"] - 1))
    record(f"gravity drop: energy ratio within 2% with gravity's work and the wall's share ({dev:.1e})",
           dev < 0.02)
    record("gravity drop: the block bounces off the wall", g["z_velocity"][-1] > 0)


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


def test_rigid_bodies():
    """*MAT_RIGID: (1) a free rigid box spinning about a non-principal axis:
    its initial energy is 1/2 M v^2 + 1/2 w.I.w with the box's closed-form
    inertia (the mass properties come from Gauss integration and the motion
    from a fit to the nodal velocities; 1e-9), and torque-free motion keeps it
    to 1e-6 over 5e4 cycles (the issue's figure); (2) an elastic rod with a
    rigid end mass vibrates at beta c / L, beta tan(beta) = m_rod / M (1%,
    the rod's discretisation)."""
    p, out = run_deck("input_decks/verify/rigid_spin.k", "rigid_spin")
    record("deck rigid_spin runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode == 0:
        g = glstat(out)
        M = 7850.0 * 0.2 * 0.1 * 0.05
        inertia = M / 12 * np.array([0.1 ** 2 + 0.05 ** 2, 0.2 ** 2 + 0.05 ** 2, 0.2 ** 2 + 0.1 ** 2])
        w = 10.0 * np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
        e0 = 0.5 * M * 1.0 ** 2 + 0.5 * np.sum(inertia * w ** 2)
        te = g["total_energy"]
        record(f"rigid spin: initial energy = 1/2 M v^2 + 1/2 w.I.w of the box ({te[0]:.9g} vs {e0:.9g})",
               abs(te[0] / e0 - 1) < roundoff(1e-9))
        dev = np.max(abs(te / te[0] - 1))
        record(f"rigid spin: energy constant to 1e-6 over 5e4 torque-free cycles ({dev:.1e})", dev < 1e-6)
        record("rigid spin: the centre keeps its velocity (1, 0, 0)",
               abs(g["x_velocity"][-1] - 1) < roundoff(1e-12) and abs(g["y_velocity"][-1]) < roundoff(1e-12))
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            L = np.stack([f["rbdout/x_angular_momentum"][:, 0], f["rbdout/y_angular_momentum"][:, 0],
                          f["rbdout/z_angular_momentum"][:, 0]])
            wz = f["rbdout/z_angular_velocity"][:, 0]
        dev = np.max(np.linalg.norm(L - L[:, :1], axis=0)) / np.linalg.norm(L[:, 0])
        record(f"rigid spin: angular momentum constant to 1e-6 (rbdout, {dev:.1e})", dev < 1e-6)
        record("rigid spin: the angular velocity wanders about a non-principal axis (torque-free precession)",
               np.ptp(wz) > 1e-3 * abs(wz).max())
    # a rigid plate of shells: inertia M/12 (b^2 + t^2, a^2 + t^2, a^2 + b^2)
    p, out = run_deck("input_decks/verify/rigid_shell_spin.k", "rigid_shell_spin")
    record("deck rigid_shell_spin runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode == 0:
        a, b, t = 0.2, 0.1, 0.002
        M = 7850.0 * a * b * t
        inertia = M / 12 * np.array([b * b + t * t, a * a + t * t, a * a + b * b])
        w = 10.0 * np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
        e0 = 0.5 * M + 0.5 * np.sum(inertia * w ** 2)
        te = glstat(out)["total_energy"]
        record(f"rigid shell plate: initial energy from the shells' inertia ({te[0] / e0 - 1:+.1e})",
               abs(te[0] / e0 - 1) < roundoff(1e-9))
        dev = np.max(abs(te / te[0] - 1))
        record(f"rigid shell plate: energy kept to 1e-6 ({dev:.1e})", dev < 1e-6)
    p, out = run_deck("input_decks/verify/rod_rigid_mass.k", "rod_rigid_mass")
    record("deck rod_rigid_mass runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode == 0:
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t, v = f["nodout/time"][:], f["nodout/x_velocity"][:, 0]
        down = [t[i - 1] + (t[i] - t[i - 1]) * v[i - 1] / (v[i - 1] - v[i]) for i in range(1, len(v))
                if v[i - 1] > 0 >= v[i]]
        period = np.mean(np.diff(down))
        E, rho, L, A = 200e9, 7850.0, 1.0, 1e-4
        mu = rho * L * A / (1.0e6 * 0.1 * 1e-4)
        lo, hi = 1e-9, 1.5
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if mid * np.tan(mid) > mu else (mid, hi)
        theory = 2 * np.pi * L / (lo * np.sqrt(E / rho))
        record(f"rod with rigid end mass: period within 1% of beta tan beta = m/M ({(period / theory - 1) * 100:+.2f}%)",
               abs(period / theory - 1) < 0.01)
        dev = np.max(abs(glstat(out)["energy_ratio"] - 1))
        record(f"rod with rigid end mass: energy ratio within 1e-3 ({dev:.1e})", dev < 1e-3)


def test_rigid_wall_bodies():
    """A *MAT_RIGID block falling at 10 m/s onto a planar rigid wall (the
    stonewall stops a rigid body's nodes by impulses on the body; before,
    the body went through the wall while the wall booked energy without
    bound). Flat landing: the body stops on the wall (a plastic impact, as a
    stonewall is for a free node): no node behind it (1e-9 m), |vz| after
    under 1e-6 m/s, the wall's energy equal to the kinetic energy (1e-6
    relative: round-off). A corner first, the mesh turned 30 and 20 degrees:
    the body turns onto the wall, no node behind it, and when it has come to
    rest (kinetic energy under 1e-5 of the start) the wall holds the
    kinetic energy to 1e-4 (the impulses' work uses the velocity before and
    after the step, as every force's does, so the balance closes when the
    body rests; at the impact cycles the ratio dips, by 23% here)."""
    for name, flat in (("rigid_block_wall", True), ("rigid_block_wall_corner", False)):
        p, out = run_deck(f"input_decks/verify/{name}.k", name)
        if p.returncode != 0:
            record(f"{name} runs", False, p.stderr[-300:])
            continue
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            g = {k: f["glstat"][k][:] for k in f["glstat"]}
            zmin = float(f["nodout/z_coordinate"][:].min())
        ke0, ke1, wall = g["kinetic_energy"][0], g["kinetic_energy"][-1], g["stonewall_energy"][-1]
        bal = abs(wall + ke1 - ke0) / ke0
        if flat:
            ok = zmin >= -1e-9 and abs(g["z_velocity"][-1]) < 1e-6 and bal < 1e-6
            record(f"rigid body on a rigid wall, flat: stops on it (lowest node z {zmin:.2e} m, vz "
                   f"{g['z_velocity'][-1]:.1e} m/s), the wall takes the kinetic energy ({bal:.1e})", ok)
        else:
            ok = zmin >= -1e-9 and ke1 < 1e-5 * ke0 and bal < 1e-4
            record(f"rigid body on a rigid wall, corner first: turns onto it (lowest node z {zmin:.2e} m), at rest "
                   f"(KE {ke1 / ke0:.1e} of the start) the wall holds the energy ({bal:.1e})", ok)


def test_rigid_constraints():
    """*BOUNDARY_PRESCRIBED_MOTION_RIGID: the block's centre follows the
    displacement curve (linear between its points, so to rounding, 1e-9 m)
    and it turns at the prescribed 2 rad/s (1e-9 rad), staying rigid.
    *CONSTRAINED_GENERALIZED_WELD_SPOT: two plates, one started at 10 m/s, move
    as one: their relative slide only oscillates (the plates vibrate in shear
    about the four weld points, amplitude about v / omega = 2 mm), under a
    quarter of the parting when the welds fail at TFAIL 1e-6 (more than 10 mm);
    momentum conserved to 1e-9."""
    p, out = run_deck("input_decks/verify/rigid_prescribed.k", "rigid_prescribed")
    record("deck rigid_prescribed runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode == 0:
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t, x, y = f["nodout/time"][:], f["nodout/x_coordinate"][:], f["nodout/y_coordinate"][:]
        ts = np.arange(41) * 0.0005
        target = np.interp(t, ts, 0.01 * np.sin(np.pi * ts / 0.02))
        ux = (x[:, 0] + x[:, 1]) / 2 - (x[0, 0] + x[0, 1]) / 2
        err = np.max(abs(ux - target))
        # (scale 0.1 m: the coordinates' size)
        record(f"prescribed rigid translation follows its curve ({err:.1e} m)", err < roundoff(1e-9, 0.1))
        ang = np.unwrap(np.arctan2(y[:, 1] - y[:, 0], x[:, 1] - x[:, 0]))
        err = np.max(abs(ang - ang[0] - 2.0 * t))
        record(f"prescribed rigid spin follows its angular velocity ({err:.1e} rad)", err < roundoff(1e-9))
        d = np.hypot(x[:, 1] - x[:, 0], y[:, 1] - y[:, 0])
        record(f"prescribed rigid block stays rigid (corner distance to {roundoff(1e-12, 0.1):.0e} m, {np.ptp(d):.1e})",
               np.ptp(d) < roundoff(1e-12, 0.1))
    gaps = {}
    for d in ("spot_weld", "spot_weld_fail"):
        p, out = run_deck(f"input_decks/verify/{d}.k", d)
        record(f"deck {d} runs (exit 0)", p.returncode == 0, p.stderr[-300:])
        if p.returncode != 0:
            return
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t = f["matsum/time"][:]
            v = f["matsum/x_momentum"][:] / f["matsum/mass"][:]
            mom = f["matsum/x_momentum"][:].sum(1)
        rel = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:, 0] - v[1:, 1] + v[:-1, 0] - v[:-1, 1]) * np.diff(t))])
        gaps[d] = np.max(abs(rel))
        record(f"{d}: momentum conserved ({abs(mom[-1] / mom[0] - 1):.1e})", abs(mom[-1] / mom[0] - 1) < roundoff(1e-9))
        dev = np.max(abs(glstat(out)["energy_ratio"] - 1))
        record(f"{d}: energy ratio within 1e-3 ({dev:.1e})", dev < 1e-3)
    record(f"spot welds hold the plates together (relative slide {gaps['spot_weld'] * 1e3:.2f} mm, under a "
           f"quarter of the {gaps['spot_weld_fail'] * 1e3:.1f} mm without them)",
           gaps["spot_weld"] < 0.25 * gaps["spot_weld_fail"])
    record(f"failed spot welds let the plates part ({gaps['spot_weld_fail'] * 1e3:.1f} mm > 10 mm)",
           gaps["spot_weld_fail"] > 1e-2)


def test_pressure():
    """*LOAD_SEGMENT_SET on the top of a column under uniaxial stress, ramped
    slowly to 100 MPa and held: the top settles at p L / E (1%: the column
    still vibrates a little about it after the ramp), and the pressure's work
    balances the energy (1%)."""
    p, out = run_deck("input_decks/verify/pressure_column.k", "pressure_column")
    record("deck pressure_column runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        t, uz = f["nodout/time"][:], f["nodout/z_displacement"][:, 0]
    theory = -1e8 * 0.1 / 200e9
    got = uz[t > 1.7e-3].mean()
    record(f"pressure: top displacement within 1% of p L / E ({(got / theory - 1) * 100:+.2f}%)",
           abs(got / theory - 1) < 0.01)
    g = glstat(out)
    w = g["total_energy"][0] + g["external_work"]
    dev = np.max(abs(g["total_energy"] - w)) / np.max(abs(w))
    record(f"pressure: its work balances the energy ({dev:.1e})", dev < 0.01)
    # the same top faces from *SET_SEGMENT_GENERAL: the column's exterior
    # faces with their centre in a box around z = 0.1 (outward, as the
    # deck's explicit segments): the same settlement, to round-off (the
    # segments come in another order, so the nodal sums may differ in the
    # last bits: 1e-9 of the displacement)
    text = open(os.path.join(ROOT, "input_decks/verify/pressure_column.k")).read()
    old = ("*SET_SEGMENT\n         1\n        91        92        95        94\n        92        93        96        95\n"
           "        94        95        98        97\n        95        96        99        98\n")
    assert old in text
    deck = os.path.join(TMP, "pressure_general.k")
    with open(deck, "w") as fh:
        fh.write(text.replace(old, "*DEFINE_BOX\n         4      -1.0       1.0      -1.0       1.0     0.099     0.101\n"
                              "*SET_SEGMENT_GENERAL\n         1\nBOX              4\n"))
    q, out2 = run_deck(deck, "pressure_general")
    ok = q.returncode == 0
    if ok:
        with h5py.File(os.path.join(out2, "thist.h5"), "r") as f:
            uz2 = f["nodout/z_displacement"][:, 0]
        diff = float(np.max(abs(uz2 - uz)) / np.max(abs(uz)))
    record(f"pressure: *SET_SEGMENT_GENERAL BOX gives the explicit segments' answer "
           f"({diff if ok else float('nan'):.1e} of the displacement)", ok and diff < 1e-9, q.stderr[-300:])


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
    # bilinear path to 0.5% (the issue's figure); the thickness is held, so
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


def shell_grid(n, first, part, e0, shift=0.0, z=0.0):
    """*NODE and *ELEMENT_SHELL lines of an n x n node grid of 2 mm shells
    centred on the origin (moved by `shift` in x and y, at height z), node
    ids from `first` row by row, elements of `part` numbered from e0 + 1."""
    nodes = [f"{first + n * j + i:8d}{(i - (n - 1) / 2) * 2e-3 + shift:16.8e}{(j - (n - 1) / 2) * 2e-3 + shift:16.8e}"
             f"{z:16.8e}" for j in range(n) for i in range(n)]
    elems = []
    for j in range(n - 1):
        for i in range(n - 1):
            b = first + n * j + i
            elems.append(f"{e0 + len(elems) + 1:8d}{part:8d}{b:8d}{b + 1:8d}{b + n + 1:8d}{b + n:8d}")
    return nodes, elems


def node_set(sid, ids):
    """*SET_NODE_LIST sid with `ids`, eight a card."""
    return ["*SET_NODE_LIST", f"{sid:10d}"] + ["".join(f"{a:10d}" for a in ids[k:k + 8]) for k in range(0, len(ids), 8)]


def write_lines(path, lines):
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    return path


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


def tied_patch_deck(z2=0.9e-3, kind="NODES_TO_SURFACE", upper_mat=1):
    """Two elastic 1 mm steel plates, a 3 x 3 patch (10 x 10.7 mm shells)
    lying z2 over a 4 x 4 plate (10 mm shells), nodes not matching, the
    patch's nodes tied to the plate (*CONTACT_TIED_..., SSTYP 4). A
    triangular pressure pulse on the patch (1 MPa peak over 40 us)."""
    L = ["*KEYWORD", "*TITLE", "tied patch", "*CONTROL_TERMINATION", " 2.000e-04",
         "*DATABASE_GLSTAT", " 1.000e-06", "*DATABASE_MATSUM", " 1.000e-06", "*DATABASE_NODOUT", " 1.000e-06",
         "*SECTION_SHELL", "         1         2         1         2", "     0.001     0.001     0.001     0.001",
         "*MAT_ELASTIC", "         1      7850     2e+11       0.3",
         "*MAT_RIGID", "         2      7850     2e+11       0.3",
         "*PART", "lower", "         1         1         1", "*PART", "upper", f"         2         1{upper_mat:10d}",
         "*NODE"]
    nid, low, up = 0, {}, {}
    for j in range(5):
        for i in range(5):
            nid += 1
            low[i, j] = nid
            L.append(f"{nid:8d}{i * 0.01:16.9e}{j * 0.01:16.9e}{0.0:16.9e}       0       0")
    for j in range(4):
        for i in range(4):
            nid += 1
            up[i, j] = nid
            L.append(f"{nid:8d}{0.005 + i * 0.01:16.9e}{0.004 + j * 0.0107:16.9e}{z2:16.9e}       0       0")
    L.append("*ELEMENT_SHELL")
    e, ups = 0, []
    for j in range(4):
        for i in range(4):
            e += 1
            L.append(f"{e:8d}       1{low[i, j]:8d}{low[i + 1, j]:8d}{low[i + 1, j + 1]:8d}{low[i, j + 1]:8d}")
    for j in range(3):
        for i in range(3):
            e += 1
            ups.append(e)
            L.append(f"{e:8d}       2{up[i, j]:8d}{up[i + 1, j]:8d}{up[i + 1, j + 1]:8d}{up[i, j + 1]:8d}")
    L += ["*SET_SHELL_LIST", "         1"] + [f"{v:10d}" for v in ups]
    L += ["*SET_NODE_LIST", "         2"] + [f"{v:10d}" for v in up.values()]
    L += ["*DEFINE_CURVE", "        50", f"{0.0:20.8e}{0.0:20.8e}", f"{2e-5:20.8e}{1e6:20.8e}",
          f"{4e-5:20.8e}{0.0:20.8e}", f"{1.0:20.8e}{0.0:20.8e}"]
    L += ["*LOAD_SHELL_SET", "         1        50         1"]
    L += ["*DATABASE_HISTORY_NODE"] + [f"{v:10d}" for v in range(1, nid + 1)]
    L += [f"*CONTACT_TIED_{kind}", "         2         1         4         3", "*END"]
    return "\n".join(L) + "\n"


def grid_nodes(L, nid, ni, nj, at):
    """*NODE lines (appended to L) of an ni x nj grid of nodes numbered on
    from nid, at(i, j) the coordinates; returns the grid {(i, j): id} and
    the last id."""
    grid = {}
    for j in range(nj):
        for i in range(ni):
            nid += 1
            grid[i, j] = nid
            x, y, z = at(i, j)
            L.append(f"{nid:8d}{x:16.9e}{y:16.9e}{z:16.9e}       0       0")
    return grid, nid


def grid_shells(L, e, grid, ni, nj, part):
    """*ELEMENT_SHELL lines (appended to L) of part `part` over a node grid
    of ni x nj nodes, numbered on from e; returns their ids."""
    ids = []
    for j in range(nj - 1):
        for i in range(ni - 1):
            e += 1
            ids.append(e)
            L.append(f"{e:8d}{part:8d}{grid[i, j]:8d}{grid[i + 1, j]:8d}{grid[i + 1, j + 1]:8d}{grid[i, j + 1]:8d}")
    return ids


def tjoint_deck(kind="SHELL_EDGE_TO_SURFACE"):
    """A T-joint: a 1 mm web (20 mm wide, 50 mm tall, 4 x 10 shells, steel,
    nu 0) stands on a base plate (40 x 40 mm, 8 x 8 shells) held fixed in
    all six degrees of freedom; its bottom edge, 0.5 mm above the base and
    between the base's nodes, is tied to the base. A pressure on the web
    ramped over 12 ms (four of its first periods) to 10.7 kPa and held."""
    L = ["*KEYWORD", "*TITLE", "T-joint: a cantilever plate tied by its edge", "*CONTROL_TERMINATION", " 1.800e-02",
         "*DATABASE_GLSTAT", " 1.000e-04", "*DATABASE_NODOUT", " 2.000e-05",
         "*SECTION_SHELL", "         1         2         1         3", "     0.001     0.001     0.001     0.001",
         "*MAT_ELASTIC", "         1      7850     2e+11       0.0",
         "*PART", "base", "         1         1         1", "*PART", "web", "         2         1         1", "*NODE"]
    base, nid = grid_nodes(L, 0, 9, 9, lambda i, j: (i * 0.005, j * 0.005, 0.0))
    web, nid = grid_nodes(L, nid, 5, 11, lambda j, k: (0.0175, 0.0125 + j * 0.005, 0.0005 + k * 0.005))
    L.append("*ELEMENT_SHELL")
    bl = grid_shells(L, 0, base, 9, 9, 1)
    wl = grid_shells(L, len(bl), web, 5, 11, 2)
    L += ["*SET_NODE_LIST", "         1"] + [f"{v:10d}" for v in base.values()]
    L += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         1         1         1"]
    L += ["*SET_NODE_LIST", "         2"] + [f"{web[j, 0]:10d}" for j in range(5)]
    L += ["*SET_SHELL_LIST", "         3"] + [f"{v:10d}" for v in wl]
    L += ["*DEFINE_CURVE", "        50", f"{0.0:20.8e}{0.0:20.8e}", f"{12e-3:20.8e}{10.7e3:20.8e}",
          f"{1.0:20.8e}{10.7e3:20.8e}"]
    L += ["*LOAD_SHELL_SET", "         3        50         1"]
    L += ["*DATABASE_HISTORY_NODE", f"{web[2, 10]:10d}{web[2, 0]:10d}"]
    L += [f"*CONTACT_TIED_{kind}", "         2         1         4         3", "*END"]
    return "\n".join(L) + "\n"


def lever_deck(kind="NODES_TO_SURFACE_OFFSET", p=7.25e3):
    """A cantilever plate (40 x 40 mm, 1 mm, 4 x 4 shells, steel, nu 0)
    clamped along x = 0, and a lever (30 x 40 mm, 3 x 4 shells) lying
    5-35 mm beside its free edge, every lever node tied to the edge with
    its gap (*CONTACT_TIED_..._OFFSET, SST 80 mm so that the tie distance
    reaches it). A pressure on the lever ramped over 16 ms (four periods)
    and held: the edge carries the lever's force P and its moment P e
    (e = 20 mm, the lever's centroid from the edge)."""
    L = ["*KEYWORD", "*TITLE", "a lever tied beside a cantilever plate's free edge", "*CONTROL_TERMINATION", " 2.400e-02",
         "*DATABASE_GLSTAT", " 1.000e-04", "*DATABASE_NODOUT", " 2.000e-05",
         "*SECTION_SHELL", "         1         2         1         3", "     0.001     0.001     0.001     0.001",
         "*MAT_ELASTIC", "         1      7850     2e+11       0.0",
         "*PART", "plate", "         1         1         1", "*PART", "lever", "         2         1         1", "*NODE"]
    pl, nid = grid_nodes(L, 0, 5, 5, lambda i, j: (i * 0.01, j * 0.01, 0.0))
    lv, nid = grid_nodes(L, nid, 4, 5, lambda i, j: (0.045 + i * 0.01, j * 0.01, 0.0))
    L.append("*ELEMENT_SHELL")
    pls = grid_shells(L, 0, pl, 5, 5, 1)
    ls = grid_shells(L, len(pls), lv, 4, 5, 2)
    L += ["*SET_NODE_LIST", "         1"] + [f"{pl[0, j]:10d}" for j in range(5)]
    L += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         1         1         1"]
    L += ["*SET_NODE_LIST", "         2"] + [f"{v:10d}" for v in lv.values()]
    L += ["*SET_SHELL_LIST", "         3"] + [f"{v:10d}" for v in ls]
    L += ["*DEFINE_CURVE", "        50", f"{0.0:20.8e}{0.0:20.8e}", f"{16e-3:20.8e}{p:20.8e}", f"{1.0:20.8e}{p:20.8e}"]
    L += ["*LOAD_SHELL_SET", "         3        50         1"]
    L += ["*DATABASE_HISTORY_NODE", f"{pl[4, 2]:10d}{lv[1, 2]:10d}"]
    L += [f"*CONTACT_TIED_{kind}", "         2         1         4         3", "       0.0       0.0       0.0       0.0",
          "       1.0       1.0      0.08       0.0", "*END"]
    return "\n".join(L) + "\n"


def tiebreak_deck(mode="normal", option=1, nfls=1e6, sfls=0.5e6, param=0.0, tend=1.5e-3, margin=0.0, cohesive=None):
    """A 2 mm steel plate (20 x 20 mm, 2 x 2 hexahedra) glued under a 10 mm
    block by a tiebreak (the plate's top nodes the slaves); every node of
    the block driven at an acceleration rising as gamma t along z (normal)
    or x (shear), gamma chosen so that the plate's inertia asks the failure
    stress of the glue at 1 ms. margin: the block's footprint wider than
    the plate's by that on every side (the plate's nodes then lie inside
    the block's face as it slides, away from its edges); cohesive: OPTION
    9's ERATEN ERATES CT2CN CN."""
    M, A = 7850 * 0.02 * 0.02 * 0.002, 4e-4
    sig = nfls if mode == "normal" else sfls
    gamma = sig * A / M / 1e-3
    L = ["*KEYWORD", "*TITLE", f"tiebreak: a plate pulled off a block ({mode})", "*CONTROL_TERMINATION",
         f"{tend:10.3e}", "*DATABASE_GLSTAT", " 1.000e-05", "*DATABASE_MATSUM", " 1.000e-05",
         "*DATABASE_NODOUT", " 2.000e-06", "*DATABASE_HISTORY_NODE", "        14        23",
         "*SECTION_SOLID", "         1         1", "*MAT_ELASTIC", "         1      7850     2e+11       0.3",
         "*PART", "plate", "         1         1         1", "*PART", "block", "         2         1         1", "*NODE"]
    nid, nd = 0, {}
    zs = {(0, 0): 0.0, (0, 1): 0.002, (1, 0): 0.002, (1, 1): 0.012}
    for b in range(2):
        for k in range(2):
            for j in range(3):
                for i in range(3):
                    nid += 1
                    nd[b, i, j, k] = nid
                    xy = [[0.0, 0.01, 0.02], [-margin, 0.01, 0.02 + margin]][b]
                    L.append(f"{nid:8d}{xy[i]:16.9e}{xy[j]:16.9e}{zs[b, k]:16.9e}       0       0")
    L.append("*ELEMENT_SOLID")
    e = 0
    for b in range(2):
        for j in range(2):
            for i in range(2):
                e += 1
                c = [nd[b, i, j, 0], nd[b, i + 1, j, 0], nd[b, i + 1, j + 1, 0], nd[b, i, j + 1, 0],
                     nd[b, i, j, 1], nd[b, i + 1, j, 1], nd[b, i + 1, j + 1, 1], nd[b, i, j + 1, 1]]
                L.append(f"{e:8d}{b + 1:8d}" + "".join(f"{v:8d}" for v in c))
    L += ["*SET_NODE_LIST", "         1"] + [f"{nd[1, i, j, k]:10d}" for k in range(2) for j in range(3) for i in range(3)]
    dof = 3 if mode == "normal" else 1
    L += ["*DEFINE_CURVE", "        50", f"{0.0:20.8e}{0.0:20.8e}", f"{1.0:20.8e}{gamma:20.8e}"]
    L += ["*BOUNDARY_PRESCRIBED_MOTION_SET", f"         1{dof:10d}         1        50       1.0"]
    L += ["*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK", "         1         2         3         3",
          "       0.0       0.0       0.0       0.0", "       1.0       1.0",
          f"{option:10d}{nfls:10.3e}{sfls:10.3e}{param:10.3e}" + "".join(f"{v:10.3e}" for v in (cohesive or ())),
          "*END"]
    return "\n".join(L) + "\n"


def cube_sphere(L, nid, R, zc, nsp):
    """The nodes of a sphere of radius R centred at z = zc (a cube's faces,
    nsp x nsp each, projected on it) appended to the deck lines L from node
    nid + 1; returns the last node id and the quadrilaterals (outward)."""
    pts, quads = {}, []

    def node(p):
        nonlocal nid
        key = tuple(np.round(p, 12))
        if key not in pts:
            nid += 1
            pts[key] = nid
            q = np.array(p) / np.linalg.norm(p) * R
            L.append(f"{nid:8d}{q[0]:16.9e}{q[1]:16.9e}{q[2] + zc:16.9e}       0       0")
        return pts[key]
    g = np.linspace(-1, 1, nsp + 1)
    for ax in range(3):
        for sgn in (-1, 1):
            for a in range(nsp):
                for b in range(nsp):
                    c = []
                    for (da, db) in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0.0, 0.0, 0.0]
                        p[ax] = sgn
                        p[(ax + 1) % 3] = g[a + da]
                        p[(ax + 2) % 3] = g[b + db]
                        c.append(node(p))
                    quads.append(c[::-1] if sgn < 0 else c)
    return nid, quads


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


def spotweld_deck(rf=1000.0, mode="normal"):
    """Two 10 x 10 mm, 5 mm steel plates 6 mm apart (mid-surfaces), joined
    at their centres by a spot weld beam (*SECTION_BEAM ELFORM 9, 5 mm
    diameter, *MAT_SPOTWELD with NRR or NRS rf) tied to each plate by
    *CONTACT_SPOTWELD. The lower plate driven along z (normal) or x (shear;
    both plates kept parallel) at an acceleration rising as gamma t, gamma
    chosen so that the upper plate's inertia (with the weld's half) asks rf
    of the weld at 1 ms."""
    M = 7850 * 0.01 * 0.01 * 0.005 + 7850 * 3.14159265 / 4 * 0.005 ** 2 * 0.006 / 2
    gamma = rf / M / 1e-3
    L = ["*KEYWORD", "*TITLE", "a spot weld pulled apart", "*CONTROL_TERMINATION", " 1.500e-03",
         "*DATABASE_GLSTAT", " 1.000e-05", "*DATABASE_MATSUM", " 1.000e-05",
         "*DATABASE_NODOUT", " 2.000e-06", "*DATABASE_HISTORY_NODE", "         5        14",
         "*SECTION_SHELL", "         1         2         1         3", "     0.005     0.005     0.005     0.005",
         "*SECTION_BEAM", "         2         9       1.0         2         0", "     0.005     0.005       0.0       0.0",
         "*MAT_ELASTIC", "         1      7850     2e+11       0.3",
         "*MAT_SPOTWELD", "         2      7850     2e+11       0.3     3e+08       0.0       0.0       0.0",
         (f"       0.0{rf:10.4g}       0.0       0.0" if mode == "normal" else f"       0.0       0.0{rf:10.4g}       0.0")
         + "       0.0       0.0       0.0",
         "*PART", "lower", "         1         1         1", "*PART", "upper", "         2         1         1",
         "*PART", "weld", "         3         2         2", "*NODE"]
    nid = 0
    for z in (0.0, 0.006):
        for j in range(3):
            for i in range(3):
                nid += 1
                L.append(f"{nid:8d}{i * 0.005:16.9e}{j * 0.005:16.9e}{z:16.9e}       0       0")
    L.append(f"{19:8d}{0.005:16.9e}{0.005:16.9e}{0.0:16.9e}       0       0")
    L.append(f"{20:8d}{0.005:16.9e}{0.005:16.9e}{0.006:16.9e}       0       0")
    L.append(f"{21:8d}{0.02:16.9e}{0.005:16.9e}{0.003:16.9e}       0       0")
    L.append("*ELEMENT_SHELL")
    e = 0
    for b in range(2):
        for j in range(2):
            for i in range(2):
                e += 1
                c = [9 * b + 3 * j + i + 1, 9 * b + 3 * j + i + 2, 9 * b + 3 * (j + 1) + i + 2,
                     9 * b + 3 * (j + 1) + i + 1]
                L.append(f"{e:8d}{b + 1:8d}" + "".join(f"{v:8d}" for v in c))
    L += ["*ELEMENT_BEAM", f"{101:8d}       3      19      20      21"]
    L += ["*SET_NODE_LIST", "         1"] + [f"{v:10d}" for v in range(1, 10)]
    dof = 3 if mode == "normal" else 1
    L += ["*DEFINE_CURVE", "        50", f"{0.0:20.8e}{0.0:20.8e}", f"{1.0:20.8e}{-gamma:20.8e}"]
    L += ["*BOUNDARY_PRESCRIBED_MOTION_SET", f"         1{dof:10d}         1        50       1.0"]
    if mode == "shear":
        # a lap joint's plates stay parallel: the lower plate driven along x
        # only, the upper free along x and y, neither turning
        L += ["*SET_NODE_LIST", "         2"] + [f"{v:10d}" for v in range(10, 19)]
        L += ["*BOUNDARY_SPC_SET", "         1         0         0         1         1         1         1         1",
              "*BOUNDARY_SPC_SET", "         2         0         0         0         1         1         1         1"]
    L += ["*CONTACT_SPOTWELD", "         3         1         3         3", "*CONTACT_SPOTWELD",
          "         3         2         3         3"]
    L += ["*END"]
    return "\n".join(L) + "\n"


def shape4(xi, eta):
    return 0.25 * np.array([(1 - xi) * (1 - eta), (1 + xi) * (1 - eta), (1 + xi) * (1 + eta), (1 - xi) * (1 + eta)])


def tie_residual(out):
    """Largest distance, over every output and every tied node d3hsp names,
    between the node and the point of its segment it was tied to (the
    segment's shape functions at that point, found from the t = 0
    positions by Newton's method)."""
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        X = np.stack([f["nodout/" + c + "_coordinate"][:] for c in "xyz"], -1)
        ids = list(f["nodout/ids"][:])
    log = open(os.path.join(out, "d3hsp")).read()
    ties = [(int(a), [int(b) for b in s.split()]) for a, s in re.findall(r"node (\d+) tied to segment ([\d ]+) \(", log)]
    worst = 0.0
    for s, seg in ties:
        i, js = ids.index(s), [ids.index(j) for j in seg]
        xm, p = X[0, js], X[0, i]
        xi = eta = 0.0
        for _ in range(30):
            r = xm.T @ shape4(xi, eta) - p
            J = np.stack([xm.T @ (0.25 * np.array([-(1 - eta), 1 - eta, 1 + eta, -(1 + eta)])),
                          xm.T @ (0.25 * np.array([-(1 - xi), -(1 + xi), 1 + xi, 1 - xi]))], 1)
            d = np.linalg.lstsq(J, -r, rcond=None)[0]
            xi, eta = xi + d[0], eta + d[1]
        res = np.linalg.norm(X[:, i] - np.einsum("tjc,j->tc", X[:, js], shape4(xi, eta)), axis=-1)
        worst = max(worst, float(res.max()))
    return worst, len(ties), float(np.abs(X[-1] - X[0]).max())


def test_tied_contact():
    """*CONTACT_TIED_NODES_TO_SURFACE and _SHELL_EDGE_TO_SURFACE (issue 33).
    The patch's 16 nodes are placed on the plate and move with it: each
    stays on the point of its segment it was tied to within 1e-6 of the
    element size (10 nm; a kinematic tie holds it to round-off) while the
    pulse moves the plates; the z momentum equals the pulse's impulse (the
    ideal 0.01926 N s on the undeformed patch; 1e-3, the pressure acting on
    the deformed, tilting patch); the energy ratio after the pulse within
    1e-6 of 1 (the tie lumps each slave's mass on its segment's nodes, and
    the kinetic energy counts it there, where the dynamics move it: they
    conserve that energy to round-off; measured 7e-11). Raised beyond the tie
    distance, no node is tied and d3hsp names each. The T-joint's web,
    tied by its edge with rotations, is a clamped cantilever: its tip's mean
    deflection over the hold q H^4 / (8 E I) within 2% (H 50.5 mm, the edge
    placed on the base's mid-surface); tied by its nodes alone (no
    rotations) it is a hinge and swings more than 20 times as far. The
    _OFFSET forms keep each slave at its gap in its segment's frame and pass
    the gap's moment to the segment: checked on a spinning pair and on a
    lever beside a cantilever's edge (below). Two MPI
    ranks give the serial histories bitwise; a slave on a rigid body is
    refused."""
    p, out, path = run_text("tied_patch", tied_patch_deck())
    if p.returncode != 0:
        record("tied contact: the tied patch runs", False, p.stderr[-300:])
        return
    worst, nt, moved = tie_residual(out)
    log = open(os.path.join(out, "d3hsp")).read()
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        pz = float(f["matsum/z_momentum"][-1].sum())
        ratio, tg = f["glstat/energy_ratio"][:], f["glstat/time"][:]
    # after the pulse (during it, the ratio of a load rising over 12 cycles
    # is the central difference's lag: the same plates untied read 0.60 at
    # cycle 2 and 0.97 at cycle 20)
    ratio = ratio[tg > 4.1e-5]
    imp = 0.5 * 1e6 * 4e-5 * 0.03 * 0.0321
    record(f"tied contact: 16 patch nodes tied ({nt}) stay on their segments' points within 1e-8 m "
           f"({worst:.1e} m) while the plates move {moved * 1e3:.3f} mm; named in d3hsp",
           nt == 16 and worst < 1e-8 and moved > 1e-4 and "16 slave nodes tied, 0 not tied" in log)
    record(f"tied contact: the patch and plate take the pulse's impulse together ({abs(pz):.6f} N s against "
           f"{imp:.6f}, 1e-3) with the energy ratio within 1e-6 of 1 ({float(np.max(np.abs(ratio - 1))):.1e})",
           abs(abs(pz) / imp - 1) < 1e-3 and float(np.max(np.abs(ratio - 1))) < 1e-6)
    p, out2, _ = run_text("tied_patch_far", tied_patch_deck(z2=2e-3))
    log2 = open(os.path.join(out2, "d3hsp")).read() if p.returncode == 0 else ""
    record("tied contact: a patch 2 mm over the plate (beyond the 1 mm tie distance) is not tied, each node named",
           p.returncode == 0 and "0 slave nodes tied, 16 not tied" in log2 and
           log2.count("not tied: no master segment within the tie distance") == 16, p.stderr[-300:])
    if shutil.which("mpirun") is not None:
        q = mpirun(2, ["i=" + path, "outdir=" + os.path.join(TMP, "tied_patch_mpi2")])
        ok, msg = (False, q.stderr[-300:]) if q.returncode else ranks_match(out, os.path.join(TMP, "tied_patch_mpi2"))
        record("tied contact: mpirun -np 2 gives the tied patch's serial histories (bitwise; owned nodes: the motion)", ok, msg)
    p, _, _ = run_text("tied_patch_rigid", tied_patch_deck(upper_mat=2))
    record("tied contact: a slave node on a rigid body is refused (exit 1) naming the node",
           p.returncode == 1 and "slave node 26 is on a rigid body" in p.stderr, p.stderr[-300:])
    # the T-joint: clamped by the tied edge's rotations, hinged without them
    EI, q, H = 2e11 * 0.02 * 1e-9 / 12, 10.7e3 * 0.02, 0.0505
    ref = q * H ** 4 / (8 * EI)
    tips = {}
    for kind in ("SHELL_EDGE_TO_SURFACE", "NODES_TO_SURFACE"):
        p, tout, tpath = run_text("tjoint_" + kind.lower(), tjoint_deck(kind))
        if p.returncode != 0:
            record(f"tied contact: the T-joint ({kind}) runs", False, p.stderr[-300:])
            return
        with h5py.File(os.path.join(tout, "thist.h5"), "r") as f:
            t, x = f["nodout/time"][:], f["nodout/x_displacement"][:, 0]
        tips[kind] = (float(np.mean(np.abs(x[t > 12e-3]))), float(np.max(np.abs(x))))
    log = open(os.path.join(TMP, "tjoint_shell_edge_to_surface", "d3hsp")).read()
    clamped = tips["SHELL_EDGE_TO_SURFACE"][0]
    record(f"tied contact: the web tied by its shell edge is a clamped cantilever: mean tip deflection "
           f"{clamped * 1e3:.4f} mm against q H^4/(8 E I) {ref * 1e3:.4f} mm (2%: {clamped / ref - 1:+.2%}); d3hsp: "
           f"5 edge nodes with rotations tied", abs(clamped / ref - 1) < 0.02 and
           "5 slave nodes with rotations tied" in log)
    record(f"tied contact: tied by its nodes alone (no rotations) the web is hinged and swings "
           f"{tips['NODES_TO_SURFACE'][1] * 1e3:.1f} mm (more than 20 x the clamped {clamped * 1e3:.3f} mm)",
           tips["NODES_TO_SURFACE"][1] > 20 * clamped)
    # the offset forms: the gap kept in the segment's frame, its moment
    # carried. The patch 0.9 mm over the plate (_OFFSET: not moved), both
    # spun about x at 200 rad/s for 8 ms (92 degrees): each patch node stays
    # 0.9 mm along the plate's turning normal from its tie point (1e-9 of
    # the gap: the velocity is set to the gap's place at the step's end),
    # the energy ratio within 1e-6 (a rigid spin: the tie's dynamics keep
    # it to round-off, measured 7e-8)
    text = tied_patch_deck(kind="NODES_TO_SURFACE_OFFSET").replace(
        "*LOAD_SHELL_SET\n         1        50         1\n", "").replace(
        " 2.000e-04\n", " 8.000e-03\n", 1)
    for db in ("GLSTAT", "MATSUM", "NODOUT"):
        text = text.replace(f"*DATABASE_{db}\n 1.000e-06", f"*DATABASE_{db}\n 1.000e-04")
    text = text.replace("*END", "*SET_PART_LIST\n        10\n         1         2\n*INITIAL_VELOCITY_GENERATION\n"
                        "        10         1     200.0       0.0       0.0       0.0\n"
                        "     0.020     0.020     0.000       1.0       0.0       0.0\n*END")
    p, sout, _ = run_text("tied_offset_spin", text)
    if p.returncode != 0:
        record("tied contact: the offset patch spinning with its plate runs", False, p.stderr[-300:])
    else:
        with h5py.File(os.path.join(sout, "thist.h5"), "r") as f:
            X = np.stack([f["nodout/" + c + "_coordinate"][:] for c in "xyz"], -1)
            ids = list(f["nodout/ids"][:])
            ratio = f["glstat/energy_ratio"][:]
        log = open(os.path.join(sout, "d3hsp")).read()
        ties = [(int(a), [int(b) for b in q.split()]) for a, q in
                re.findall(r"node (\d+) tied to segment ([\d ]+) \(kept at its gap", log)]
        worst = 0.0
        for sn, seg in ties:
            i, js = ids.index(sn), [ids.index(j) for j in seg]
            xm0 = X[0, js]
            # the flat segment's bilinear map is affine: the tie point's
            # (xi, eta) from the slave's x and y at t = 0
            N = shape4((X[0, i, 0] - xm0[:, 0].mean()) / 0.005, (X[0, i, 1] - xm0[:, 1].mean()) / 0.005)
            for t in range(X.shape[0]):
                xm = X[t, js]
                n = np.cross(xm[2] - xm[0], xm[3] - xm[1])
                n /= np.linalg.norm(n)
                worst = max(worst, float(np.linalg.norm(X[t, i] - xm.T @ N - 0.9e-3 * n)))
        n0 = np.cross(X[0, ids.index(7)] - X[0, ids.index(1)], X[0, ids.index(6)] - X[0, ids.index(2)])
        n1 = np.cross(X[-1, ids.index(7)] - X[-1, ids.index(1)], X[-1, ids.index(6)] - X[-1, ids.index(2)])
        turn = float(np.degrees(np.arccos(n0 @ n1 / np.linalg.norm(n0) / np.linalg.norm(n1))))
        dev = float(np.max(np.abs(ratio - 1)))
        record(f"tied contact: _OFFSET keeps 16 patch nodes at their 0.9 mm gap along the plate's normal while "
               f"the pair spins {turn:.0f} degrees ({worst / 0.9e-3:.1e} of the gap, 1e-9), energy ratio within "
               f"1e-6 ({dev:.1e})", len(ties) == 16 and worst < 0.9e-12 and turn > 80 and dev < 1e-6)
    # the lever: the edge carries the lever's force and moment; its mean
    # deflection over the hold against P L^3/3EI + P e L^2/2EI (3%: the
    # lever's load spread over its nodes, measured -1.3%); the force alone
    # would give 57% of it
    EI, P, Lc, e = 2e11 * 0.04 * 1e-9 / 12, 7.25e3 * 0.03 * 0.04, 0.04, 0.02
    both, alone = P * Lc ** 3 / (3 * EI) + P * e * Lc ** 2 / (2 * EI), P * Lc ** 3 / (3 * EI)
    p, lout, _ = run_text("tied_offset_lever", lever_deck())
    if p.returncode != 0:
        record("tied contact: the offset lever runs", False, p.stderr[-300:])
    else:
        with h5py.File(os.path.join(lout, "thist.h5"), "r") as f:
            t, z = f["nodout/time"][:], f["nodout/z_displacement"][:, 0]
            tg, ratio = f["glstat/time"][:], f["glstat/energy_ratio"][:]
        mean = float(np.mean(np.abs(z[t > 16e-3])))
        dev = float(np.max(np.abs(ratio[tg > 6e-3] - 1)))
        record(f"tied contact: a lever tied 5-35 mm beside a cantilever's edge (_OFFSET) loads it with its force "
               f"and moment: edge deflection {mean * 1e3:.4f} mm against {both * 1e3:.4f} (3%: {mean / both - 1:+.1%}; "
               f"the force alone {alone * 1e3:.4f}); energy ratio within 1e-3 after 6 ms ({dev:.1e})",
               abs(mean / both - 1) < 0.03 and dev < 1e-3)
    if shutil.which("mpirun") is not None:
        tout = os.path.join(TMP, "tjoint_shell_edge_to_surface")
        q2 = mpirun(2, ["i=" + tout + ".k", "outdir=" + tout + "_mpi2"])
        ok, msg = (False, q2.stderr[-300:]) if q2.returncode else ranks_match(tout, tout + "_mpi2")
        record("tied contact: mpirun -np 2 gives the T-joint's serial histories (bitwise; owned nodes: the motion; rotations tied)", ok, msg)


def test_tiebreak():
    """*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK, OPTION 1 and 2
    (issue 33). A plate glued under a block, the block driven so that the
    plate's inertia asks the glue's failure stress at 1 ms. The stress at
    opening is measured from the motion, not from the tie: the time the
    plate first moves from the block (0.1 um, outputs 2 us apart) and the
    stress the plate's inertia asked then, M gamma t / A. Normal: within 5% of NFLS 1 MPa; shear: within 5% of SFLS 0.5 MPa
    (the block's pull also bends the plate: the nodes break under 0.1 MPa
    of tension with 0.4975 MPa of shear, on the criterion's circle). OPTION 2 keeps
    the force at failure and lets it fall to zero over PARAM 0.5 mm of
    separation: the sliding interface energy reaches 1/2 F A PARAM (5%) and
    the energy ratio stays within 1e-3. Two ranks give the serial
    histories bitwise, and a restart mid-softening the uninterrupted run's."""
    M, A = 7850 * 0.02 * 0.02 * 0.002, 4e-4
    for mode, sig, comp in (("normal", 1e6, "z_momentum"), ("shear", 0.5e6, "x_momentum")):
        p, out, path = run_text("tiebreak_" + mode, tiebreak_deck(mode))
        if p.returncode != 0:
            record(f"tiebreak ({mode}) runs", False, p.stderr[-300:])
            continue
        gamma = sig * A / M / 1e-3
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t, P = f["matsum/time"][:], f[f"matsum/{comp}"][:, 0]
            ratio = f["glstat/energy_ratio"][:]
        # the opening: the first output (every 2 us) at which the plate's
        # centre node has moved from the block's node above it by 0.1 um
        # (glued, the two move together to round-off); the stress the
        # plate's inertia asked of the glue then, M gamma t / A, and one
        # output earlier
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            tn = f["nodout/time"][:]
            rel = np.stack([f["nodout/" + c + "_displacement"][:, 0] - f["nodout/" + c + "_displacement"][:, 1]
                            for c in "xyz"], -1)
        k = next((i for i in range(len(tn)) if np.linalg.norm(rel[i]) > 1e-7), None)
        if k is None or k == 0:
            record(f"tiebreak ({mode}): the glue opens", False, "the plate never moved from the block")
            continue
        s_lo, s_hi = M * gamma * tn[k - 1] / A, M * gamma * tn[k] / A
        log = open(os.path.join(out, "d3hsp")).read()
        nb = log.count("broke at time")
        record(f"tiebreak ({mode}): the glue opens between {s_lo / 1e6:.4f} and {s_hi / 1e6:.4f} MPa (the plate's "
               f"inertia's demand when it first moves from the block), against {sig / 1e6:.1f} MPa (5%: {s_lo / sig - 1:+.2%} to "
               f"{s_hi / sig - 1:+.2%}); 9 nodes named as broken ({nb}); energy ratio within 1e-3 "
               f"({float(np.max(np.abs(ratio - 1))):.1e})",
               abs(s_lo / sig - 1) < 0.05 and abs(s_hi / sig - 1) < 0.05 and nb == 9 and
               float(np.max(np.abs(ratio - 1))) < 1e-3)
        if mode == "normal" and shutil.which("mpirun") is not None:
            q = mpirun(2, ["i=" + path, "outdir=" + out + "_mpi2"])
            ok, msg = (False, q.stderr[-300:]) if q.returncode else ranks_match(out, out + "_mpi2")
            record("tiebreak: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)", ok, msg)
    p, out, _ = run_text("tiebreak_option2", tiebreak_deck("normal", option=2, param=0.5e-3, tend=3e-3))
    if p.returncode != 0:
        record("tiebreak OPTION 2 runs", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        slide, ratio = f["glstat/sliding_interface_energy"][-1], f["glstat/energy_ratio"][:]
        P2 = f["matsum/z_momentum"][-1, 0]
    with h5py.File(os.path.join(TMP, "tiebreak_normal", "thist.h5"), "r") as f:
        P1 = f["matsum/z_momentum"][-1, 0]
    want = 0.5 * 1e6 * A * 0.5e-3
    # a restart dump at 1.2 ms, between the break (1.0 ms) and the end of
    # the softening (about 1.3 ms), carries the ties' state: the restarted
    # run ends as the uninterrupted one, bitwise
    text = tiebreak_deck("normal", option=2, param=0.5e-3, tend=3e-3).replace(
        "*END", "*DATABASE_BINARY_D3DUMP\n         0\n*END")
    path = os.path.join(TMP, "tiebreak_rs.k")
    with open(path, "w") as f:
        f.write(text)
    full, part = os.path.join(TMP, "tiebreak_rs_full"), os.path.join(TMP, "tiebreak_rs_part")
    q1 = run([XDYNA, "i=" + path, "outdir=" + full, "endtim=2e-3"])
    q2 = run([XDYNA, "i=" + path, "outdir=" + part, "endtim=1.2e-3"])
    q3 = run([XDYNA, "r=" + os.path.join(part, "d3dump.h5"), "endtim=2e-3"])
    ok, msg = ((False, (q1.stderr + q2.stderr + q3.stderr)[-300:]) if q1.returncode or q2.returncode or q3.returncode
               else same_histories(full, part))
    record("tiebreak OPTION 2: a restart from 1.2 ms, mid-softening, ends as the uninterrupted run (bitwise)", ok, msg)
    record(f"tiebreak OPTION 2: the interface takes {slide:.5f} J as it opens over PARAM, against 1/2 NFLS A PARAM "
           f"{want:.5f} J (5%: {slide / want - 1:+.2%}); the plate leaves with more momentum than under OPTION 1 "
           f"({P2:.4f} against {P1:.4f} N s); energy ratio within 1e-3 ({float(np.max(np.abs(ratio - 1))):.1e})",
           abs(slide / want - 1) < 0.05 and P2 > P1 * 1.1 and float(np.max(np.abs(ratio - 1))) < 1e-3)


def test_tiebreak_cohesive():
    """*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK OPTION 9, the
    mixed-mode cohesive law (issue 33; the law itself against its
    definition: the unit test test_contact_tied). The plate glued under a
    block 5 mm wider on every side (the plate's nodes stay inside the
    block's face as it slides: its edges would push them), T 1 MPa, S 0.5
    MPa, GIC = GIIC = 100 J/m^2, CN 1e12 Pa/m. The interface force is
    measured from the motion, as the plate's momentum rate (only the glue
    holds it; outputs 2 us apart): its peak over the area within 5% of T
    (normal pull) and of S (shear); the interface's work when every node
    has broken within 5% of GIC A and GIIC A (what the law releases); all
    9 nodes named as softening and as broken; energy ratio within 1e-3. Two
    ranks give the serial histories, and a restart mid-softening the
    uninterrupted run's, bitwise."""
    A, G = 4e-4, 100.0
    coh = (G, G, 1.0, 1e12)
    for mode, want, comp in (("normal", 1e6, "z_momentum"), ("shear", 0.5e6, "x_momentum")):
        text = tiebreak_deck(mode, option=9, param=1.0, tend=1.6e-3, margin=0.005, cohesive=coh).replace(
            "*DATABASE_MATSUM\n 1.000e-05", "*DATABASE_MATSUM\n 2.000e-06")
        p, out, path = run_text("tiebreak9_" + mode, text)
        if p.returncode != 0:
            record(f"tiebreak OPTION 9 ({mode}) runs", False, p.stderr[-300:])
            continue
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t, P = f["matsum/time"][:], f[f"matsum/{comp}"][:, 0]
            slide, ratio = f["glstat/sliding_interface_energy"][-1], f["glstat/energy_ratio"][:]
        peak = float(np.max(np.diff(P) / np.diff(t))) / A
        log = open(os.path.join(out, "d3hsp")).read()
        ns, nb = log.count("began to soften"), log.count("broke at time")
        dev = float(np.max(np.abs(ratio - 1)))
        record(f"tiebreak OPTION 9 ({mode}): the plate's momentum rate peaks at {peak / 1e6:.4f} MPa over the glued "
               f"area, against {want / 1e6:.1f} MPa (5%: {peak / want - 1:+.2%}); the interface takes {slide:.5f} J "
               f"against {'GIC' if mode == 'normal' else 'GIIC'} A {G * A:.5f} J (5%: {slide / (G * A) - 1:+.2%}); 9 "
               f"nodes named softening ({ns}) and broken ({nb}); energy ratio within 1e-3 ({dev:.1e})",
               abs(peak / want - 1) < 0.05 and abs(slide / (G * A) - 1) < 0.05 and ns == 9 and nb == 9 and dev < 1e-3)
        if mode == "normal" and shutil.which("mpirun") is not None:
            q = mpirun(2, ["i=" + path, "outdir=" + out + "_mpi2"])
            ok, msg = (False, q.stderr[-300:]) if q.returncode else ranks_match(out, out + "_mpi2")
            record("tiebreak OPTION 9: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)", ok, msg)
        if mode == "normal":
            text = text.replace("*END", "*DATABASE_BINARY_D3DUMP\n         0\n*END")
            path = os.path.join(TMP, "tiebreak9_rs.k")
            with open(path, "w") as f:
                f.write(text)
            full, part = os.path.join(TMP, "tiebreak9_rs_full"), os.path.join(TMP, "tiebreak9_rs_part")
            q1 = run([XDYNA, "i=" + path, "outdir=" + full, "endtim=1.2e-3"])
            q2 = run([XDYNA, "i=" + path, "outdir=" + part, "endtim=1.05e-3"])
            q3 = run([XDYNA, "r=" + os.path.join(part, "d3dump.h5"), "endtim=1.2e-3"])
            ok, msg = ((False, (q1.stderr + q2.stderr + q3.stderr)[-300:])
                       if q1.returncode or q2.returncode or q3.returncode else same_histories(full, part))
            record("tiebreak OPTION 9: a restart from 1.05 ms, mid-softening, ends as the uninterrupted run (bitwise)",
                   ok, msg)


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


def ranks_match(serial, out):
    """(ok, message): an MPI run (in out) against the serial run: bitwise
    where it kept the replicated nodal state; with owned nodes (d3hsp says
    which), its motion bitwise and its energies to rounding (same_dynamics)."""
    log = os.path.join(out, "d3hsp")
    if os.path.exists(log) and "nodal state: owned nodes" in open(log).read():
        return same_dynamics(serial, out)
    return same_histories(serial, out)


def two_ranks_match(path, out):
    """(ok, message): mpirun -np 2 on the deck at path gives the serial
    run's (in out) histories (ranks_match)."""
    q = mpirun(2, ["i=" + path, "outdir=" + out + "_mpi2"])
    return (False, q.stderr[-300:]) if q.returncode else ranks_match(out, out + "_mpi2")


def restart_matches(name, text, t_dump, t_end=None):
    """(ok, message): the deck text with a restart dump, run to t_end (the
    deck's end where None) whole, and to t_dump then restarted from its
    dump to t_end, gives the same histories bitwise."""
    rs = os.path.join(TMP, name + ".k")
    with open(rs, "w") as f:
        f.write(text.replace("*END", "*DATABASE_BINARY_D3DUMP\n         0\n*END"))
    full, part = os.path.join(TMP, name + "_full"), os.path.join(TMP, name + "_part")
    end = [] if t_end is None else [f"endtim={t_end!r}"]
    q1 = run([XDYNA, "i=" + rs, "outdir=" + full] + end)
    q2 = run([XDYNA, "i=" + rs, "outdir=" + part, f"endtim={t_dump!r}"])
    q3 = run([XDYNA, "r=" + os.path.join(part, "d3dump.h5")] + end)
    if q1.returncode or q2.returncode or q3.returncode:
        return False, (q1.stderr + q2.stderr + q3.stderr)[-300:]
    return same_histories(full, part)


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


def mat_id_of(deck):
    """The id of a deck's first material (the card after its first *MAT_)."""
    lines = deck.splitlines()
    for i, line in enumerate(lines):
        if line.startswith("*MAT_"):
            j = i + 1
            while lines[j].startswith("$"):
                j += 1
            return int(lines[j][:10])
    return 0


NRB_INERTIA_DECK = """*KEYWORD
*TITLE
a nodal rigid body with its own inertia
*CONTROL_TERMINATION
      0.05
*DATABASE_GLSTAT
    0.0001
*DATABASE_NODOUT
    0.0001
*DATABASE_HISTORY_NODE
         1         2         3
*SECTION_SHELL
         1         2
     0.001     0.001     0.001     0.001
*MAT_ELASTIC
         1      7850     2e+11       0.3
*PART
bystander
         1         1         1
*NODE
      11             1.0             1.0             1.0       0       0
      12            1.01             1.0             1.0       0       0
      13            1.01            1.01             1.0       0       0
      14             1.0            1.01             1.0       0       0
       1             0.0             0.0             0.0       0       0
       2             0.1             0.0             0.0       0       0
       3             0.0             0.1             0.0       0       0
*ELEMENT_SHELL
       1       1      11      12      13      14
*ELEMENT_MASS
       1       1             0.1       0
       2       2             0.1       0
       3       3             0.1       0
*SET_NODE_LIST
         1
         1         2         3
*CONSTRAINED_NODAL_RIGID_BODY_INERTIA
         9         0         1
      0.02      0.02       0.0       2.0         0         0
      0.01       0.0       0.0      0.02       0.0      0.03
       1.0       0.0       0.0       0.0       0.0      10.0
*END
"""


def test_nodal_rigid_inertia():
    """*CONSTRAINED_NODAL_RIGID_BODY_INERTIA: three nodes (0.1 kg point
    masses each) made a rigid body whose mass (2 kg), centre and inertia
    (diag 0.01, 0.02, 0.03 kg m2) the deck gives, moving at 1 m/s along x
    and spinning at 10 rad/s about z. Its kinetic energy is the body's,
    1/2 M v^2 + 1/2 w.I.w = 2.5 J (1e-9; the nodes' own masses would give
    0.15 J of translation), and every node follows the rigid motion about
    the given centre, xc + v t + R(w t)(x0 - xc), within 1e-9 m over half a
    radian (a lone shell elsewhere sets the step)."""
    p, out, _ = run_text("nrb_inertia", NRB_INERTIA_DECK)
    if p.returncode != 0:
        record("nodal rigid body _INERTIA runs", False, p.stderr[-300:])
        return
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        ke = f["glstat/kinetic_energy"][:]
        t = f["nodout/time"][:]
        X = np.stack([f["nodout/" + c + "_coordinate"][:] for c in "xyz"], -1)
    xc0, v, w = np.array([0.02, 0.02, 0.0]), np.array([1.0, 0.0, 0.0]), 10.0
    err = 0.0
    for i, tt in enumerate(t):
        c, s_ = math.cos(w * tt), math.sin(w * tt)
        R = np.array([[c, -s_, 0.0], [s_, c, 0.0], [0.0, 0.0, 1.0]])
        err = max(err, float(np.abs(X[i] - (xc0 + v * tt + (R @ (X[0] - xc0).T).T)).max()))
    record(f"nodal rigid body _INERTIA: kinetic energy {ke[-1]:.12g} J is the body's 2.5 J (1e-9 relative, "
           f"throughout), nodes on the rigid motion about the deck's centre within 1e-9 m ({err:.1e}) over "
           f"{w * t[-1]:.2f} rad", float(np.max(np.abs(ke / 2.5 - 1))) < 1e-9 and err < 1e-9 and w * t[-1] > 0.45)


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
        print("SKIP beams in the d3plot: VTK's LS-DYNA reader (Debian's python3-vtk9) is not installed")
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


def test_spotweld():
    """Spot welds (issue 33): a *MAT_SPOTWELD beam (ELFORM 9) tied to two
    plates by *CONTACT_SPOTWELD (rotations tied, the nodes at their gaps),
    pulled apart (normal) and sheared. It fails at its resultant criterion:
    the plates part when the upper plate's inertia asks NRR (axial) or NRS
    (shear, the end moments' sum over the length) of the weld, within 5%
    (the opening read from the motion: the first output, 2 us apart, at
    which the plates' centres have moved 10 um apart; glued, the weld
    stretches 1.5 um and shears 2.8 um); d3hsp names the failure; the
    energy ratio within 1e-6. Two ranks give the serial histories
    bitwise."""
    for mode, c, col in (("normal", "z", 1), ("shear", "x", 2)):
        p, out, path = run_text("spotweld_" + mode, spotweld_deck(mode=mode))
        if p.returncode != 0:
            record(f"spot weld ({mode}) runs", False, p.stderr[-300:])
            continue
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            t = f["nodout/time"][:]
            d = f[f"nodout/{c}_displacement"][:, 1] - f[f"nodout/{c}_displacement"][:, 0]
            ratio = f["glstat/energy_ratio"][:]
        k = next((i for i in range(len(t)) if abs(d[i]) > 1e-5), None)
        # the weld's load rises as (the upper side's mass) gamma t, rf at 1 ms
        lo, hi = (t[k - 1] / 1e-3, t[k] / 1e-3) if k else (float("nan"), float("nan"))
        log = open(os.path.join(out, "d3hsp")).read()
        dev = float(np.max(np.abs(ratio - 1)))
        record(f"spot weld ({mode}): the plates part when the weld carries {lo:.4f} to {hi:.4f} of its "
               f"{'NRR' if mode == 'normal' else 'NRS'} (5%); the failure named in d3hsp; energy ratio within 1e-6 "
               f"({dev:.1e})", k is not None and abs(lo - 1) < 0.05 and abs(hi - 1) < 0.05 and dev < 1e-6 and
               "spot weld beam 101 of part 3 failed at time" in log)
        if mode == "normal" and shutil.which("mpirun") is not None:
            q = mpirun(2, ["i=" + path, "outdir=" + out + "_mpi2"])
            ok, msg = (False, q.stderr[-300:]) if q.returncode else ranks_match(out, out + "_mpi2")
            record("spot weld: mpirun -np 2 gives the serial histories (bitwise; owned nodes: the motion)", ok, msg)


def test_spotweld_plastic():
    """*MAT_SPOTWELD's plasticity (issue 33): a weld beam (ELFORM 9, 5 mm
    diameter, 6 mm long; SIGY 300 MPa, EH 2 GPa, EFAIL 0.1) held at one end
    and pulled along its axis at 1 m/s, both ends otherwise fixed (the
    force follows the kinematics alone). Past yield its axial force (the
    d3plot.h5 resultants, every 20 us) is A (SIGY + EH eps_p) with eps_p =
    ln(l/L) - N/(E A) (the rate form integrates the logarithmic strain;
    the area is the section's): N = A (SIGY + EH ln(l/L)) / (1 + EH/E),
    within 1% at every state from 20 us to the failure; the weld fails when
    eps_p reaches EFAIL, at l = L exp(EFAIL + N/(E A)) (the time within
    1%), named in d3hsp with its plastic strain; the energy ratio within
    1e-3 up to then. The check can fail: perfectly plastic (EH 0) the force
    would stay at 5.89 kN, against 9.5 kN at the end."""
    L0, E, A, sy, eh, ef = 0.006, 2e11, np.pi / 4 * 0.005 ** 2, 3e8, 2e9, 0.1
    deck = "\n".join([
        "*KEYWORD", "*TITLE", "a spot weld pulled along its axis past yield to EFAIL", "*CONTROL_TERMINATION",
        " 8.000e-04", "*DATABASE_GLSTAT", " 1.000e-05", "*DATABASE_BINARY_D3PLOT", " 2.000e-05",
        "*SECTION_BEAM", "         1         9       1.0         2         0", "     0.005     0.005       0.0       0.0",
        "*MAT_SPOTWELD", f"         1      7850     2e+11       0.3{sy:10.3g}{eh:10.3g}       0.0       0.0",
        f"{ef:10.3g}       0.0       0.0       0.0       0.0       0.0       0.0",
        "*PART", "weld", "         1         1         1", "*NODE",
        "       1             0.0             0.0             0.0       0       0",
        f"       2             0.0             0.0{L0:16.9e}       0       0",
        "       3            0.01             0.0             0.0       0       0",
        "*ELEMENT_BEAM", "       1       1       1       2       3",
        "*BOUNDARY_SPC_NODE", "         1         0         1         1         1         1         1         1",
        "         2         0         1         1         0         1         1         1",
        "*DEFINE_CURVE", "         1", "                 0.0                 1.0", "                 1.0                 1.0",
        "*BOUNDARY_PRESCRIBED_MOTION_NODE", "         2         3         0         1       1.0", "*END"]) + "\n"
    path = os.path.join(TMP, "spotweld_plastic.k")
    with open(path, "w") as f:
        f.write(deck)
    out = os.path.join(TMP, "spotweld_plastic")
    p = run([XDYNA, "i=" + path, "outdir=" + out, "h5plot=1"])
    if p.returncode != 0:
        record("spot weld plasticity runs", False, p.stderr[-300:])
        return
    log = open(os.path.join(out, "d3hsp")).read()
    m = re.search(r"spot weld beam 1 of part 1 failed at time\s+(\S+) .*plastic strain\s+(\S+)\)", log)
    with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
        keys = sorted(k for k in f["states"] if k != "time")
        t = f["states/time"][:]
        N = np.array([f[f"states/{k}/beam_resultants"][0, 0] for k in keys])
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        tg, ratio = f["glstat/time"][:], f["glstat/energy_ratio"][:]
    if m is None:
        record("spot weld plasticity: the weld fails at EFAIL, named in d3hsp", False, log[-400:])
        return
    tf = float(m.group(1))
    sel = (t > 1e-5) & (t < tf)
    lr = np.log(1 + t[sel] / L0)
    want = A * (sy + eh * lr) / (1 + eh / E)
    err = float(np.max(np.abs(N[sel] / want - 1)))
    # the failure: eps_p = EFAIL, N there from the same law
    nf = A * (sy + eh * ef)
    tf_want = L0 * (np.exp(ef + nf / (E * A)) - 1)
    dev = float(np.max(np.abs(ratio[tg < tf] - 1)))
    record(f"spot weld plasticity: past yield the axial force is A (SIGY + EH eps_p) at {int(sel.sum())} states "
           f"(1%: largest {err:.2%}; {N[sel][0] / 1e3:.2f} to {N[sel][-1] / 1e3:.2f} kN); it fails at {tf * 1e3:.4f} ms "
           f"against {tf_want * 1e3:.4f} ms, where eps_p reaches EFAIL 0.1 (1%: {tf / tf_want - 1:+.2%}), named in d3hsp "
           f"with its plastic strain {m.group(2)}; energy ratio within 1e-3 ({dev:.1e})",
           sel.sum() > 20 and err < 0.01 and abs(tf / tf_want - 1) < 0.01 and abs(float(m.group(2)) / ef - 1) < 0.01
           and dev < 1e-3)


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


def test_subsystems():
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
    log = open(os.path.join(TMP, "bar_impact", "d3hsp")).read()
    record("solids-only deck: the log lists shells and rigid bodies off",
           "shell elements ............ off" in log and "rigid bodies .............. off" in log)


def test_malformed():
    """(d) Each malformed deck exits 1, its message contains the expected
    file:line, keyword, card, field and text, and only the log is written."""
    decks = sorted(glob.glob(os.path.join(ROOT, "tests", "decks", "malformed", "*.k")))
    record(f"at least 15 malformed decks ({len(decks)})", len(decks) >= 15)
    for deck in decks:
        name = os.path.basename(deck)
        with open(deck) as f:
            expect = [l[len("$ expect: "):].rstrip("\n") for l in f if l.startswith("$ expect: ")]
        out = os.path.join(TMP, "malformed", name)
        os.makedirs(out, exist_ok=True)
        p = run([XDYNA, "i=" + name, "outdir=" + out], cwd=os.path.dirname(deck))
        missing = [e for e in expect if e not in p.stderr]
        files = sorted(os.listdir(out))
        ok = p.returncode == 1 and expect and not missing and files == ["d3hsp"]
        record(f"malformed {name}: exit 1, message names the place, only d3hsp written", ok,
               f"rc={p.returncode} files={files} stderr={p.stderr.strip()[:300]!r} missing={missing}")


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
        print("SKIP states: pvpython is not installed (Debian's paraview); the XDMF was checked with h5py only")
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


def with_cards(src_deck, name, cards):
    """A copy of src_deck (under TMP) with `cards` inserted after *KEYWORD."""
    text = open(os.path.join(ROOT, src_deck)).read()
    deck = os.path.join(TMP, name + ".k")
    with open(deck, "w") as fh:
        fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n" + cards, 1))
    return deck


def same_histories(a, b):
    """thdiff at zero tolerance, the same number of rows in every series, and
    the ASCII files equal but for the wall-clock timing lines."""
    q = run([THDIFF, os.path.join(a, "thist.h5"), os.path.join(b, "thist.h5"), "--rtol", "0", "--atol", "0"])
    rows = True
    with h5py.File(os.path.join(a, "thist.h5"), "r") as fa, h5py.File(os.path.join(b, "thist.h5"), "r") as fb:
        for g in fa:
            rows = rows and g in fb and fa[g]["time"].shape == fb[g]["time"].shape
    ascii_same = all(la == lb for _, la, lb in ascii_histories(a, b))
    return q.returncode == 0 and rows and ascii_same, q.stdout[-300:]


def ascii_histories(a, b):
    """(name, lines of a, lines of b) of each ASCII history file run a
    wrote (b's empty where it has none), the header and wall-clock timing
    lines left out."""
    out = []
    for name in ("glstat", "matsum", "nodout", "rcforc", "rwforc"):
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if os.path.exists(pa):
            la = [x for x in open(pa).read().splitlines()[2:] if "time per zone" not in x]
            lb = [x for x in open(pb).read().splitlines()[2:] if "time per zone" not in x] if os.path.exists(pb) else []
            out.append((name, la, lb))
    return out


def printed_close(la, lb, atol=0.0):
    """Lines of an ASCII history equal token by token, a number allowed to
    differ by one unit of its last printed digit (values that agree to
    1e-12 relative round to the same digits but at a rounding boundary) or
    by atol."""
    if len(la) != len(lb):
        return False
    for x, y in zip(la, lb):
        if x == y:
            continue
        tx, ty = x.split(), y.split()
        if len(tx) != len(ty):
            return False
        for a, b in zip(tx, ty):
            if a == b:
                continue
            m = re.fullmatch(r"-?\d*\.(\d+)[eE]([-+]\d+)", a)
            try:
                fa, fb = float(a), float(b)
            except ValueError:
                return False
            unit = 10.0 ** (int(m.group(2)) - len(m.group(1))) if m else 0.0
            if abs(fa - fb) > max(1.01 * unit, atol):
                return False
    return True


def same_dynamics(a, b, rtol=1e-12):
    """The histories of a run with owned nodes (issue 32) against the serial
    run's: every series bitwise but those of glstat and matsum (energies,
    momenta, mean velocities), which are each rank's own nodes' and
    elements' sums added over the ranks: another order of the same terms
    than one rank's single sum, so they agree to rounding. An energy within
    rtol of its series' peak (thdiff's rule); a momentum or mean velocity,
    whose terms cancel (a model at rest on the whole, parts moving
    apart), within rtol of the size of its terms: sqrt(2 KE M) for a
    part's momentum, sqrt(2 KE / M) for the model's mean velocity, KE the
    largest kinetic energy and M the mass (matsum's, or the initial nodal
    mass d3hsp gives); the ASCII lines to
    the last printed digit or those bounds. The motion, forces and stresses
    are the serial run's bit for bit."""
    energy = ("glstat", "matsum")
    bad = []
    with h5py.File(os.path.join(a, "thist.h5"), "r") as fa, h5py.File(os.path.join(b, "thist.h5"), "r") as fb:
        mass = fa["matsum/mass"][()] if "matsum/mass" in fa else None
        kep = fa["matsum/kinetic_energy"][()] if "matsum/kinetic_energy" in fa else None
        ke = float(np.max(np.abs(fa["glstat/kinetic_energy"][()]))) if "glstat/kinetic_energy" in fa else 0.0
        mtot = float(np.max(np.sum(mass, axis=1))) if mass is not None and mass.size else 0.0
        if mtot == 0.0:
            # (no matsum: the model's mass from d3hsp)
            m = re.search(r"initial nodal mass \(the nodes' lumped masses\) \.+ +(\S+)",
                          open(os.path.join(a, "d3hsp")).read())
            mtot = float(m.group(1)) if m else 0.0
        vscale = (2.0 * ke / mtot) ** 0.5 if mtot > 0 else 0.0
        names = []
        fa.visititems(lambda k, v: names.append(k) if isinstance(v, h5py.Dataset) else None)
        for k in names:
            if k not in fb or fa[k].shape != fb[k].shape:
                bad.append(k + " (missing or shape)")
                continue
            x, y = fa[k][()], fb[k][()]
            if k.split("/")[0] in energy and x.dtype.kind == "f" and x.size:
                peak = np.max(np.abs(x), axis=0)
                if k.startswith("glstat/") and k.endswith("_velocity"):
                    peak = np.maximum(peak, vscale)
                elif k.startswith("matsum/") and k.endswith("_momentum") and mass is not None:
                    peak = np.maximum(peak, np.sqrt(2.0 * np.max(np.abs(kep), axis=0) * np.max(mass, axis=0)))
                d = np.max(np.abs(x - y), axis=0)
                if np.any(d > rtol * peak):
                    bad.append(f"{k} {float(np.max(d)):.3e} of {float(np.max(peak)):.3e}")
            elif not np.array_equal(x, y):
                bad.append(k)
    atol = rtol * max(ke, vscale, (2.0 * ke * mtot) ** 0.5)
    for name, la, lb in ascii_histories(a, b):
        if not (printed_close(la, lb, atol) if name in energy else la == lb):
            bad.append(name + " (ASCII)")
    return not bad, "; ".join(bad[:5])

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


def vtk_blocks(reader):
    """The blocks of a vtkLSDynaReader's output: (name, grid) for each part."""
    out = reader.GetOutput()
    blocks = []
    for i in range(out.GetNumberOfBlocks()):
        b = out.GetBlock(i)
        if b is not None:
            blocks.append((out.GetMetaData(i).Get(out.NAME()), b))
    return blocks


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
        print("SKIP d3plot: VTK's LS-DYNA reader (Debian's python3-vtk9) is not installed")
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


def test_sense_switches():
    """LS-DYNA's sense switches, written into d3kil in the output directory
    before the run starts (the run reads it at cycle 50, then deletes it):
    sw1 writes a restart dump and stops with exit 3, and the restart ends
    as the uninterrupted run (zero tolerance); sw3 writes a dump and the
    run goes on unchanged; sw4 adds one state and changes nothing else; a
    word that is no switch is named in d3hsp and ignored. Each failed before
    d3kil was read (the runs ignored it)."""
    deck = os.path.join(ROOT, "input_decks/contact/tube_crush.k")
    full = os.path.join(TMP, "sw_full")
    shutil.rmtree(full, ignore_errors=True)
    run([XDYNA, "i=" + deck, "outdir=" + full, "endtim=1.0e-3"])

    def with_switch(word, name):
        out = os.path.join(TMP, name)
        shutil.rmtree(out, ignore_errors=True)
        os.makedirs(out)
        with open(os.path.join(out, "d3kil"), "w") as f:
            f.write(word + "\n")
        p = run([XDYNA, "i=" + deck, "outdir=" + out, "endtim=1.0e-3"])
        log = open(os.path.join(out, "d3hsp")).read() if os.path.exists(os.path.join(out, "d3hsp")) else ""
        return p, out, log, not os.path.exists(os.path.join(out, "d3kil"))

    def states(out):
        m = re.search(r"states: (\d+) written", open(os.path.join(out, "d3hsp")).read())
        return int(m.group(1)) if m else -1

    p, out, log, gone = with_switch("sw1", "sw_sw1")
    dumped = os.path.exists(os.path.join(out, "d3dump.h5"))
    record("sense switch sw1: a restart dump and exit 3 at the cycle d3kil is read (50), d3kil deleted",
           p.returncode == 3 and dumped and gone and "cycle 50: stopped by sense switch sw1" in p.stderr + log,
           f"rc={p.returncode} {p.stderr[-200:]}")
    q = run([XDYNA, "r=" + os.path.join(out, "d3dump.h5"), "endtim=1.0e-3"])
    ok, msg = same_histories(full, out)
    record("sense switch sw1: the restart completes as the uninterrupted run (zero tolerance)",
           q.returncode == 0 and ok, msg + q.stderr[-200:])
    p, out, log, gone = with_switch("sw3", "sw_sw3")
    ok, msg = same_histories(full, out)
    record("sense switch sw3: a restart dump written, the run goes on to normal termination unchanged",
           p.returncode == 0 and gone and os.path.exists(os.path.join(out, "d3dump.h5")) and ok
           and "sw3 (restart dump, the run goes on)" in log, msg + p.stderr[-200:])
    p, out, log, gone = with_switch("sw4", "sw_sw4")
    ok, msg = same_histories(full, out)
    record(f"sense switch sw4: one state more ({states(out)} against {states(full)}), the histories unchanged",
           p.returncode == 0 and gone and ok and states(out) == states(full) + 1, msg + p.stderr[-200:])
    p, out, log, gone = with_switch("hello", "sw_hello")
    record("sense switch: a word that is no switch is named in d3hsp and ignored",
           p.returncode == 0 and gone and '"hello" read from d3kil' in log and "not a sense switch" in log,
           p.stderr[-200:])


def test_batch_signals():
    """Batch operation on the tube crush (2 ms): SIGUSR2
    prints a status line; SIGTERM writes a restart dump and stops with exit
    3, and the restart completes identically to the uninterrupted run
    (thdiff at zero tolerance); wallclock=W stops with a dump (exit 3)
    before W seconds, and its restart is identical too. The signals come
    while the run is held at a cycle (XDYNA_HOLD_AT), never after a sleep;
    the wall-clock case is held at cycle 100 for 1.5 s of its 2 s, so it
    cannot end before the guard stops it however fast the machine."""
    import signal
    import time
    deck = "input_decks/contact/tube_crush.k"
    full = os.path.join(TMP, "batch_full")
    run([XDYNA, "i=" + os.path.join(ROOT, deck), "outdir=" + full, "endtim=2.0e-3"])
    out = os.path.join(TMP, "batch_sig")
    shutil.rmtree(out, ignore_errors=True)
    e = dict(os.environ)
    e.setdefault("OMP_NUM_THREADS", "1")
    # the run holds at cycle 200 (XDYNA_HOLD_AT, a hook for tests) and says
    # so; the signals come after that line, so they hit the run mid-way on
    # any machine (a fixed sleep raced the run on a fast one: it finished
    # before SIGTERM came)
    # SIGUSR2 at the first hold lets it go on (with a status line), SIGTERM
    # at the second stops it
    e["XDYNA_HOLD_AT"] = "200,201"
    proc = subprocess.Popen([XDYNA, "i=" + os.path.join(ROOT, deck), "outdir=" + out, "endtim=2.0e-3"],
                            cwd=ROOT, env=e, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    head = ""
    for sig in (signal.SIGUSR2, signal.SIGTERM):
        first = proc.stdout.readline()
        head += first
        while first and not first.startswith(" held at cycle"):
            first = proc.stdout.readline()
            head += first
        proc.send_signal(sig)
    so, se = proc.communicate(timeout=120)
    so = head + so
    status = sum(1 for line in so.splitlines() if line.startswith(" cycle"))
    record(f"batch: SIGUSR2 prints a status line ({status} progress lines, the first one and the status)",
           status >= 2, so[-300:])
    dumped = os.path.exists(os.path.join(out, "d3dump.h5"))
    record("batch: SIGTERM mid-run stops with exit 3 and a restart dump at the cycle held",
           proc.returncode == 3 and dumped and "cycle 201:" in se, f"rc={proc.returncode} {se[-200:]}")
    q = run([XDYNA, "r=" + os.path.join(out, "d3dump.h5"), "endtim=2.0e-3"])
    ok, msg = same_histories(full, out)
    record("batch: the restart after SIGTERM completes identically (thdiff at zero tolerance)",
           q.returncode == 0 and ok, msg + q.stderr[-200:])
    out = os.path.join(TMP, "batch_wall")
    shutil.rmtree(out, ignore_errors=True)
    # held at cycle 100 for 1.5 s of its 2 (then 1.5 s plus the guard's
    # margin, 0.1 s and 0.5 s, reach the limit: it stops at the next cycle),
    # so the run cannot end first however fast the machine (the 2 ms took
    # 2.3 s here once the contact got faster; a slow machine's guard stops
    # it before the hold)
    e = dict(os.environ)
    e.setdefault("OMP_NUM_THREADS", "1")
    e["XDYNA_HOLD_AT"] = "100"
    t0 = time.time()
    proc = subprocess.Popen([XDYNA, "i=" + os.path.join(ROOT, deck), "outdir=" + out, "endtim=2.0e-3", "wallclock=2"],
                            cwd=ROOT, env=e, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(1.5)
    proc.send_signal(signal.SIGUSR2)
    so, se = proc.communicate(timeout=120)
    took = time.time() - t0
    record(f"batch: wallclock=2 stops with exit 3 and a dump before the limit ({took:.2f} s)",
           proc.returncode == 3 and took < 2.0 and os.path.exists(os.path.join(out, "d3dump.h5")), se[-200:])
    q = run([XDYNA, "r=" + os.path.join(out, "d3dump.h5"), "endtim=2.0e-3"])
    ok, msg = same_histories(full, out)
    record("batch: the restart after the wall-clock stop completes identically", q.returncode == 0 and ok, msg)
    # a killed run (SIGKILL: no chance to close anything) leaves every
    # finished state readable, and every history row up to thist.h5's last
    # flush (a second of wall time at most before the kill; also at a hold)
    import xml.etree.ElementTree as ET
    kdeck = os.path.join(TMP, "killed.k")
    with open(kdeck, "w") as fh:
        fh.write(re.sub(r"\*DATABASE_BINARY_D3PLOT\n.*\n", "*DATABASE_BINARY_D3PLOT\n   5.0e-05\n",
                        open(os.path.join(ROOT, deck)).read()))
    out = os.path.join(TMP, "batch_killed")
    shutil.rmtree(out, ignore_errors=True)
    # killed while held at cycle 400 (t = 0.28 ms: states at 0, 50, ..., 250 us
    # are out), so the kill lands mid-run on any machine
    e["XDYNA_HOLD_AT"] = "400"
    proc = subprocess.Popen([XDYNA, "i=" + kdeck, "outdir=" + out, "endtim=1.0e-3"], cwd=ROOT, env=e,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    line = proc.stdout.readline()
    while line and not line.startswith(" held at cycle"):
        line = proc.stdout.readline()
    proc.kill()
    proc.wait()
    try:
        with h5py.File(os.path.join(out, "d3plot.h5"), "r") as f:
            t = f["states/time"][:]
            for k in range(1, len(t) + 1):
                f[f"states/{k:06d}/coordinates"][:]
                f[f"states/{k:06d}/shell_stress"][:]
        root = ET.parse(os.path.join(out, "d3plot.xdmf")).getroot()
        nx = sum(1 for g in root.iter("Grid") if g.get("CollectionType") == "Spatial")
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            rows = len(f["glstat/time"])
        good = len(t) >= 2 and nx == len(t) and rows >= 2
        detail = f"{len(t)} states, {nx} in the XDMF, {rows} glstat rows"
    except (OSError, KeyError, ET.ParseError) as err:
        good, detail = False, str(err)
    record(f"batch: after SIGKILL mid-run every finished state and every history row flushed reads back ({detail})",
           good)


def test_slurm_example():
    """doc/slurm/xdyna.sbatch run outside SLURM with stand-ins for squeue
    (62 s left: XDYNA_WALLCLOCK 2 s), srun (runs the command) and scontrol
    (records the requeue): the tube crush to 1 ms stops with a dump (exit 3)
    and asks for a requeue; each next start finds the dump and restarts
    from it, until the run ends normally, with the histories of an
    uninterrupted run (thdiff at zero tolerance). The first start does not
    race the clock: srun's stand-in holds it at cycle 100 (XDYNA_HOLD_AT)
    and lets it go after 3 s, past its 2 s, so it stops on the limit however
    fast the machine (it ran the whole 1 ms in 1.1 s here, within the
    limit, once the contact got faster)."""
    stub = os.path.join(TMP, "slurm_stubs")
    os.makedirs(stub, exist_ok=True)
    log = os.path.join(TMP, "slurm_requeue.log")
    mark = os.path.join(TMP, "slurm_first_start")
    srun = (f'shift\nif [ ! -f {mark} ]; then\n    touch {mark}\n    XDYNA_HOLD_AT=100 "$@" &\n'
            '    pid=$!\n    sleep 3\n    kill -USR2 $pid 2> /dev/null\n    wait $pid\n    exit $?\nfi\nexec "$@"')
    for name, body in (("squeue", "echo 1:02"), ("srun", srun),
                       ("scontrol", f'echo "$@" >> {log}')):
        path = os.path.join(stub, name)
        with open(path, "w") as fh:
            fh.write("#!/bin/sh\n" + body + "\n")
        os.chmod(path, 0o755)
    out = os.path.join(TMP, "slurm_run")
    shutil.rmtree(out, ignore_errors=True)
    deck = with_cards("input_decks/contact/tube_crush.k", "slurm_tube", "")
    with open(deck) as fh:
        text = fh.read()
    with open(deck, "w") as fh:
        fh.write(text.replace("     0.006", "     0.001", 1))
    env = {"PATH": stub + ":" + os.environ["PATH"], "SLURM_JOB_ID": "42", "SLURM_CPUS_PER_TASK": "1",
           "SLURM_SUBMIT_DIR": ROOT}
    script = os.path.join(ROOT, "doc", "slurm", "xdyna.sbatch")
    p1 = run(["bash", script, deck, out], env=env)
    requeued = os.path.exists(log) and "requeue 42" in open(log).read()
    record("slurm example: the first start stops with a dump before its time (exit 3) and requeues",
           p1.returncode == 3 and requeued and os.path.exists(os.path.join(out, "d3dump.h5")),
           p1.stdout[-300:] + p1.stderr[-300:])
    starts = 1
    p2 = p1
    while p2.returncode == 3 and starts < 8:
        p2 = run(["bash", script, deck, out], env=env)
        starts += 1
    full = os.path.join(TMP, "slurm_full")
    run([XDYNA, "i=" + deck, "outdir=" + full])
    ok, msg = same_histories(full, out)
    record(f"slurm example: each requeued start restarts from the dump; after {starts} starts the run ends "
           f"like an uninterrupted one", p2.returncode == 0 and starts > 1 and ok,
           msg + p2.stdout[-200:] + p2.stderr[-200:])


def test_format_rules():
    """Every format rule of KEYWORDS.md in one deck, and LONG=Y, give results
    bitwise identical to the plain deck (thdiff with zero tolerance)."""
    pb, ob = run_deck("tests/decks/format_rules/plain.k", "fmt_plain")
    for deck in ("rules.k", "long.k"):
        pa, oa = run_deck("tests/decks/format_rules/" + deck, "fmt_" + deck)
        q = run([THDIFF, oa, ob, "--rtol", "0", "--atol", "0"])
        record(f"format rules: {deck} runs exactly as plain.k", pa.returncode == 0 and pb.returncode == 0
               and q.returncode == 0, pa.stderr[-300:] + q.stdout[-300:])
    # the same deck with DOS line ends (CR LF) and tabs nowhere: identical run
    crlf = os.path.join(TMP, "plain_crlf.k")
    with open(os.path.join(ROOT, "tests/decks/format_rules/plain.k")) as f:
        text = f.read()
    with open(crlf, "w", newline="") as f:
        f.write(text.replace("\n", "\r\n"))
    pc, oc = run_deck(crlf, "fmt_crlf")
    q = run([THDIFF, oc, ob, "--rtol", "0", "--atol", "0"])
    record("format rules: a deck with CR LF line ends runs exactly as with LF", pc.returncode == 0 and
           q.returncode == 0, pc.stderr[-300:] + q.stdout[-300:])
    with open(os.path.join(TMP, "fmt_rules.k", "d3hsp")) as f:
        log = f.read()
    record("format rules: output-only keyword skipped with one warning",
           log.count("*DATABASE_EXTENT_BINARY is output-only") == 1)
    # keywords that tune another code or ask for outputs xdyna does not
    # write are read and named, not refused (a deck opening with *KEYWORD_ID
    # stopped at line 1 before); the answer is the plain deck's, bitwise;
    # *DATABASE_HISTORY_NODE_ID's node joins nodout
    foreign = os.path.join(TMP, "fmt_foreign.k")
    with open(foreign, "w") as f:
        f.write(text.replace("*KEYWORD\n", "*KEYWORD_ID\nproject 42\n*CONTROL_MPP_IO_NODUMP\n*CONTROL_ACCURACY\n"
                             "         1         4\n*DATABASE_ABSTAT\n   1.0e-3\n*DATABASE_HISTORY_NODE_ID\n"
                             "         7 a heading\n", 1))
    pf, of = run_deck(foreign, "fmt_foreign")
    q = run([THDIFF, of, ob, "--rtol", "0", "--atol", "0", "--only", "glstat,matsum"])
    log = open(os.path.join(of, "d3hsp")).read() if pf.returncode == 0 else ""
    named = all(k in log for k in ('*KEYWORD_ID job identification "project 42"', "*CONTROL_MPP_IO_NODUMP is output-only",
                                   "field OSU 1", "field INN 4", "*DATABASE_ABSTAT is output-only"))
    nodes = []
    if pf.returncode == 0:
        with h5py.File(os.path.join(of, "thist.h5"), "r") as f:
            nodes = sorted(f["nodout/ids"][:].tolist())
    record(f"foreign keywords: *KEYWORD_ID, *CONTROL_MPP_IO_NODUMP, *CONTROL_ACCURACY, *DATABASE_ABSTAT read and "
           f"named in d3hsp, the run bitwise the plain deck's; *DATABASE_HISTORY_NODE_ID adds its node (nodout {nodes})",
           pf.returncode == 0 and q.returncode == 0 and named and nodes == [3, 7, 12],
           pf.stdout[-300:] + pf.stderr[-300:] + q.stdout[-300:])
    p = run([XDYNA, "--check", "i=tests/decks/malformed/unknown_keyword.k", "unsupported=warn"])
    record("unsupported=warn turns an unknown keyword into a warning", p.returncode == 0 and
           "*FOO_BAR is not a supported keyword" in p.stdout, p.stdout[-300:] + p.stderr[-300:])


def test_runtime_error():
    """A run that goes bad stops with exit 2 naming element, part and time;
    the histories written so far stay readable."""
    # (the hexahedron crushed at 100 km/s was inverted at cycle 2 by a step
    # 33 times its first; since the step grows by 0.1% a cycle at most,
    # issue 28, the crush is followed in small steps and stops at cycle
    # 1,200 on the energy check, naming its node 7 of part 17: either
    # stop names the element or its node, its part and the time)
    p, out = run_deck("tests/decks/runtime/negative_volume.k", "negative_volume")
    record("negative volume: exit 2 naming solid 42 (or its node 7) of part 17 and the time",
           p.returncode == 2 and ("negative volume in solid 42 of part 17" in p.stderr
                                  or "node 7 (part 17)" in p.stderr) and "at time" in p.stderr,
           f"rc={p.returncode} {p.stderr[-300:]}")
    try:
        g = glstat(out)
        ok = len(g["time"]) >= 1
    except OSError:
        ok = False
    record("negative volume: thist.h5 readable after the error termination", ok)
    # issue 18, finding 1: runs that went bad and ended "normal termination"
    # (the two velocity decks stopped before issue 18 too: they stay as
    # regression decks; the rigid ones ended "normal termination" before)
    # The ramp to 1e7 m/s ended "normal termination" with a kinetic energy
    # of -1e29; then it stopped at cycle 100 on an energy blow-up, which was
    # the step's feedback on the element's ringing (issue 28). With the
    # step's growth limited it integrates: the cube is drawn into a needle,
    # the kinetic energy equal to the prescribed motion's work. Either end
    # is right if the state is possible: run to 1 ms (85,000 cycles; the
    # whole 8 ms takes 5.4 million), and a normal end must keep the energy
    # ratio within 5e-3 of 1 and the kinetic energy non-negative at every
    # output (what the old end broke; measured: 1.2e-3 at the first output,
    # 40 us into the ramp, under 3e-4 from the third on).
    p, out = run_deck("tests/decks/runtime/velocity_ramp_1e7.k", "velocity_ramp_1e7", extra=("endtim=0.001",))
    last = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else ""
    if p.returncode == 0:
        g = glstat(out)
        ok = bool(np.all(np.abs(g["energy_ratio"] - 1) < 5e-3) and np.all(g["kinetic_energy"] >= 0))
        what = (f"normal end in a possible state (energy ratio within {np.abs(g['energy_ratio'] - 1).max():.1e} "
                f"of 1, kinetic energy {g['kinetic_energy'][-1]:.2e} J = work {g['external_work'][-1]:.2e} J)")
    else:
        ok = p.returncode == 2 and "error termination at time" in last and re.search(r"(node|solid|shell) \d+", last)
        what = last[:160]
    record(f"velocity_ramp_1e7 (to 1 ms): exit 2 with the cause, or a normal end in a possible state ({what})",
           bool(ok), p.stderr[-300:])
    for name in ("velocity_curve_1e30", "rigid_curve_12", "rigid_displacement_1e30", "rigid_spin_1e30"):
        p, out = run_deck(f"tests/decks/runtime/{name}.k", name)
        last = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else ""
        # the cause names the node or element where it shows
        record(f"{name}: exit 2, 'error termination' with the cause, node or element and time ({last[:160]})",
               p.returncode == 2 and "error termination at time" in last
               and re.search(r"(node|solid|shell) \d+", last) is not None and "***" not in last, p.stderr[-300:])


def test_fuzz():
    """make fuzz for 45 s with a fixed seed (issue 18): mutated decks (fields
    set to NaN, Inf, huge, tiny or garbage values, bytes flipped, cards
    dropped or doubled, files cut short, keywords renamed, includes split
    off, missing, a directory, /dev/null or the deck itself) through the
    reader and 30 cycles; every outcome must be a valid run with a possible
    state, an input error naming the file, or an error termination with a
    cause: no crash, no hang, no silent acceptance. The seed is fixed so the
    same decks come each time; how many fit in 45 s depends on the machine
    (45 s since 2026-11-27, 60 before: make check had grown to its 15
    minutes; about 70 mutated decks here, 50 asked)."""
    keep = os.path.join(TMP, "fuzz_failures")
    summary = os.path.join(TMP, "fuzz_summary.txt")
    q = run([sys.executable, os.path.join(ROOT, "tools", "fuzz.py"), "--seconds", "45", "--seed", "1",
             "--keep", keep, "--summary", summary])
    line = open(summary).read().strip() if os.path.exists(summary) else q.stdout[-300:]
    # the classes of both parts of the line: mutated decks, then damaged
    # dumps and FIFOs (refused)
    counts = {}
    for k, v in re.findall(r"\b(valid|input|run|signal|refused|FAIL) (\d+)", line):
        counts[k] = counts.get(k, 0) + int(v)
    record(f"fuzz 45 s, seed 1: no crash, hang or silent acceptance ({line})",
           q.returncode == 0 and counts.get("FAIL", 0) == 0 and sum(counts.values()) - counts.get("refused", 0) >= 50
           and counts.get("refused", 0) >= 4, q.stdout[-600:])


def test_thdiff():
    """(e) thdiff accepts a run against itself and rejects a perturbed one."""
    base = os.path.join(TMP, "bar_impact")
    if not os.path.isdir(base):
        record("thdiff tests need the bar run", False)
        return
    q = run([THDIFF, base, base, "--rtol", "0"])
    record("thdiff: a run against itself passes at zero tolerance (h5)", q.returncode == 0, q.stdout[-300:])
    pert = os.path.join(TMP, "bar_perturbed")
    shutil.rmtree(pert, ignore_errors=True)
    shutil.copytree(base, pert)
    with h5py.File(os.path.join(pert, "thist.h5"), "r+") as f:
        d = f["glstat/kinetic_energy"]
        d[50] = d[50] * 1.001
    q = run([THDIFF, base, pert, "--rtol", "1e-4"])
    record("thdiff: a 0.1% change in one kinetic energy value is rejected at rtol 1e-4",
           q.returncode == 1 and "glstat/kinetic_energy" in q.stdout and "FAIL" in q.stdout, q.stdout[-400:])
    q = run([THDIFF, base, pert, "--rtol", "1e-2"])
    record("thdiff: the same change passes at rtol 1e-2", q.returncode == 0, q.stdout[-300:])
    # ASCII files: perturb one glstat value in the text
    os.remove(os.path.join(pert, "thist.h5"))
    os.remove(os.path.join(base + "_ascii_copy", "thist.h5")) if os.path.isdir(base + "_ascii_copy") else None
    lines = open(os.path.join(pert, "glstat")).read().split("\n")
    k = [i for i, l in enumerate(lines) if l.startswith(" internal energy")][40]
    val = float(lines[k][32:])
    lines[k] = lines[k][:32] + f"{val * 1.01:14.5E}"
    open(os.path.join(pert, "glstat"), "w").write("\n".join(lines))
    q = run([THDIFF, os.path.join(base, "glstat"), os.path.join(pert, "glstat"), "--rtol", "1e-3"])
    record("thdiff: a 1% change in an ASCII glstat value is rejected", q.returncode == 1, q.stdout[-300:])
    # a run directory without matsum against one with it (issue 30, finding
    # 8: "all series within tolerance", exit 0): the series of one run only
    # are a difference, unless --common asks for the common ones
    nomat = os.path.join(TMP, "bar_no_matsum")
    shutil.rmtree(nomat, ignore_errors=True)
    shutil.copytree(base, nomat)
    for name in ("thist.h5", "matsum"):
        os.remove(os.path.join(nomat, name))
    ascii_base = os.path.join(TMP, "bar_ascii_only")
    shutil.rmtree(ascii_base, ignore_errors=True)
    shutil.copytree(base, ascii_base)
    os.remove(os.path.join(ascii_base, "thist.h5"))
    q = run([THDIFF, ascii_base, nomat, "--rtol", "0"])
    q2 = run([THDIFF, ascii_base, nomat, "--rtol", "0", "--common"])
    record("thdiff: a run without matsum fails against one with it (its series named as in one run only); "
           "--common passes", q.returncode == 1 and "matsum" in q.stdout and q2.returncode == 0,
           q.stdout[-300:] + q2.stdout[-200:])
    q = run([THDIFF, os.path.join(base, "nodout"), os.path.join(base, "thist.h5"), "--common", "--only", "nodout",
             "--rtol", "1e-4", "--atol", "1e-12"])
    record("thdiff: ASCII nodout and thist.h5 of one run agree (ASCII has 5 digits)", q.returncode == 0,
           q.stdout[-300:])
    # a run stopped halfway is not the same run (issue 18, finding 4): the
    # bar to 75 us against the bar to 150 us at zero tolerance fails and
    # names the ends; --overlap compares the common times and passes
    p, half = run_deck("input_decks/verify/bar_impact.k", "bar_half", extra=("endtim=7.5e-5",))
    q = run([THDIFF, half, base, "--rtol", "0"])
    record("thdiff: a run that ends at half time fails against the full run, naming the last common time",
           p.returncode == 0 and q.returncode == 1 and "last common time" in q.stdout, q.stdout[-400:])
    q = run([THDIFF, half, base, "--rtol", "0", "--overlap"])
    record("thdiff --overlap: the same pair passes over the common times", q.returncode == 0, q.stdout[-400:])
    ref = "/dev/null"
    q = run([THDIFF, base, ref])
    record("thdiff: unreadable input exits 2", q.returncode == 2, q.stdout[-200:] + q.stderr[-200:])


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


def mpirun(np_, args, threads=1, env_extra=None):
    """xdyna on np_ MPI ranks with `threads` OpenMP threads each: Open MPI
    as root needs the two ALLOW variables, and more ranks than this machine's
    2 cores need --oversubscribe; with threads, ranks are not bound to a core.
    env_extra: more variables for the ranks."""
    cmd = ["mpirun", "--oversubscribe", "-np", str(np_)]
    env = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMP_NUM_THREADS": str(threads),
           **(env_extra or {})}
    if threads > 1:
        # more threads than cores: threads that spin at OpenMP barriers while
        # the other rank's hold the cores made 2 x 2 on 2 cores 80 times
        # slower (243 s against 2.9 s); passive waiting sleeps instead
        cmd += ["--bind-to", "none"]
        env["OMP_WAIT_POLICY"] = "passive"
    return run(cmd + [XDYNA, *args], env=env)


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


def test_mpi():
    """MPI domain decomposition (issue 8). Every node's force is summed in
    the serial slot order and the contacts in slave order, so the motion is
    the serial run's bit for bit for 1, 2 and 4 ranks (oversubscribed on
    this 2-core machine, which changes timing only). These models run with
    owned nodes (issue 32), whose energies, momenta and mean velocities are
    each rank's sums added over the ranks: those agree to rounding
    (same_dynamics: 1e-12 of their scale), every other series bitwise."""
    if shutil.which("mpirun") is None:
        record("mpirun is installed (make deps: openmpi-bin)", False)
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
    if shutil.which("mpirun") is None:
        record("mpirun is installed (make deps: openmpi-bin)", False)
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


def test_mpi_contact_own():
    """XDYNA_CONTACT_OWN=1 (issue 32, the first step of ghosts by
    proximity): each rank bounds the motion of its own contact surface
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
    if shutil.which("mpirun") is None:
        record("mpirun is installed (make deps: openmpi-bin)", False)
        return
    env = {"XDYNA_CONTACT_OWN": "1"}
    deck = with_cards("input_decks/contact/tube_crush.k", "own_tube", "*DATABASE_BINARY_D3DUMP\n         0\n")
    p0, serial = run_deck(deck, "own_serial", extra=("endtim=0.002",))
    for n in (2, 4):
        out = os.path.join(TMP, f"own{n}")
        p = mpirun(n, ["i=" + deck, "outdir=" + out, "endtim=0.002"], env_extra=env)
        ok, msg = (False, p.stderr[-300:]) if p.returncode or p0.returncode else same_dynamics(serial, out)
        named = ok and "bounds the motion of its own surface nodes alone" in open(os.path.join(out, "d3hsp")).read()
        record(f"XDYNA_CONTACT_OWN: the tube crush on {n} ranks, each bounding its own surface nodes' motion, gives "
               "the serial run's motion bitwise, energies to 1e-12 (named in d3hsp)", ok and named, msg)
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
    # XDYNA_GHOSTS=1 on top: the surfaces' velocities only to the ranks
    # whose slaves read them, chosen at each search from gathered
    # positions and every rank's box: the tube crush (self-contact) and the
    # front frame (rigid bodies, a rigid wall, two interfaces) on 2 and 4
    # ranks, and the tube restarted across rank counts, the serial motion
    # bitwise; and the two bars of two_bars_penalty.k, each on its own
    # rank, whose every contact is across ranks (with each rank's box
    # shrunk to its slaves alone, the other bar's nodes were not sent and
    # kept their positions of the last search: the bars' run differed from
    # the serial one, checked by hand when this was written).
    genv = {"XDYNA_CONTACT_OWN": "1", "XDYNA_GHOSTS": "1"}
    frame = "input_decks/paper/front_frame.k"
    bars = "input_decks/contact/two_bars_penalty.k"
    pf, fserial = run_deck(frame, "ghost_frame_serial", extra=("endtim=0.003",))
    pb, bserial = run_deck(bars, "ghost_bars_serial")
    for label, dk, ref, end in (("tube crush", deck, serial, "endtim=0.002"),
                                ("front frame", os.path.join(ROOT, frame), fserial, "endtim=0.003"),
                                ("two bars (each on its rank: every contact across ranks)", os.path.join(ROOT, bars),
                                 bserial, "endcyc=1000000000")):
        for n in (2, 4):
            out = os.path.join(TMP, f"ghost{n}_{label.replace(' ', '_')}")
            p = mpirun(n, ["i=" + dk, "outdir=" + out, end], env_extra=genv)
            ok, msg = (False, p.stderr[-300:]) if p.returncode or p0.returncode or pf.returncode or pb.returncode \
                else same_dynamics(ref, out)
            m = re.search(r"contact ghosts \(rank 0\): lists made (\d+) times", open(os.path.join(out, "d3hsp")).read()) \
                if ok else None
            record(f"XDYNA_GHOSTS: the {label} on {n} ranks with contact ghosts by proximity gives the serial run's "
                   f"motion bitwise, energies to 1e-12 ({m.group(1) if m else 0} ghost lists)",
                   ok and m is not None and int(m.group(1)) > 1, msg)
    part = os.path.join(TMP, "ghost_rs")
    p1 = mpirun(2, ["i=" + deck, "outdir=" + part, "endtim=0.0014"], env_extra=genv)
    p2 = mpirun(4, ["r=" + os.path.join(part, "d3dump.h5"), "endtim=0.002"], env_extra=genv) \
        if p1.returncode == 0 else p1
    ok, msg = same_dynamics(serial, part) if p2.returncode == 0 else (False, (p1.stderr + p2.stderr)[-300:])
    record("XDYNA_GHOSTS: the tube crush dumped on 2 ranks at 1.4 ms and restarted on 4 gives the serial run's "
           "motion bitwise", ok, msg)


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
    if shutil.which("mpirun") is None:
        record("mpirun is installed (make deps: openmpi-bin)", False)
        return
    d = os.path.join(TMP, "owned")
    os.makedirs(d, exist_ok=True)
    plate, hexes = os.path.join(d, "plate.k"), os.path.join(d, "hex.k")
    gen = [sys.executable, os.path.join(ROOT, "tools", "gen_decks.py")]
    run(gen + ["--bench-shells", "40", "30", plate, "--cycles", "200", "--states-dt", "2e-5"])
    run(gen + ["--bench", "20", "10", "6", hexes, "--cycles", "200"])
    text = open(plate).read().replace("*KEYWORD\n", "*KEYWORD\n*DATABASE_BINARY_D3DUMP\n         0\n"
                                      "*DATABASE_NODOUT\n1.0e-6\n*DATABASE_HISTORY_NODE\n1,21,641,660,1271\n", 1)
    with open(plate, "w") as fh:
        fh.write(text)
    # the plate again under a moving rigid wall 2 mm above it (NSID 0: every
    # node; mass 2 kg) and a prescribed velocity on its far edge (nodes
    # 1231-1271, across the cuts) ramped from 30 m/s to 0: the wall's
    # mass, impulse, force and energy and the prescribed work are sums
    # over nodes of every rank, taken in the serial order
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
            record(f"owned nodes, {label}: {n} ranks x {threads} threads give the serial motion and states "
                   f"bitwise, the energies to 1e-12; rank 0 integrates {share:.2f} of the nodes",
                   ok and states and m is not None and share <= 1.0 / n + 0.2, msg)
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
    log = {}
    for name, deck in (("tube", "input_decks/contact/tube_crush.k"), ("frame", "input_decks/paper/front_frame.k")):
        out = os.path.join(d, name)
        p = mpirun(2, ["i=" + os.path.join(ROOT, deck), "outdir=" + out, "endcyc=2"])
        log[name] = open(os.path.join(out, "d3hsp")).read() if p.returncode == 0 else ""
    pat = r"the contact surfaces' (\d+) nodes' velocities and the rigid bodies' (\d+) nodes' forces to every rank"
    m = re.search(pat, log["tube"])
    record(f"owned nodes: the tube crush's contact runs with owned nodes ({m.group(1) if m else 0} surface nodes' "
           "velocities to every rank)", m is not None and int(m.group(1)) > 0)
    m = re.search(pat, log["frame"])
    record(f"owned nodes: the front frame's rigid bodies and contact run with owned nodes ({m.group(2) if m else 0} "
           "body nodes' forces to every rank)", m is not None and int(m.group(2)) > 0)

def test_stability():
    """The stiff and extreme cases of `make stability` (tools/stability.py,
    issues 9 and 18): each finishes with its energy ratio in its band and no
    NaN in thist.h5 or d3plot.h5 (a stop fails every case LS-DYNA would run:
    all of them; the nu 0.4999 block on a wall stopped before issue 18); none
    may hang (300 s). The scaled solid step is named in d3hsp."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import stability
    stability.OUT = os.path.join(TMP, "stability")
    os.makedirs(stability.OUT, exist_ok=True)
    for case in stability.CASES:
        r = stability.run_case(*case)
        record(f"stability {r['name']}: {r['outcome']}", r["ok"])
    log = open(os.path.join(stability.OUT, "nu_0.4999", "d3hsp")).read()
    m = re.search(r"steps are scaled by ([0-9.]+)", log)
    # the free 4 x 4 x 4 block's highest frequency allows 0.85 of L/c at
    # nu 0.4999 (eigenvalues, numpy): the scale with its 2% margin lies
    # within 0.80-0.86
    record(f"stability: the nu 0.4999 block's solid steps are scaled for its free corners ({m.group(1) if m else 'none'})",
           m is not None and 0.80 <= float(m.group(1)) <= 0.86)


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


def test_cli():
    p = run([XDYNA, "--help"])
    record("--help prints usage and exits 0", p.returncode == 0 and "usage: xdyna i=deck.k" in p.stdout)
    p = run([XDYNA, "--version"])
    record("--version prints the version", p.returncode == 0 and p.stdout.startswith("xdyna "))
    here = os.path.join(TMP, "check_only")
    os.makedirs(here, exist_ok=True)
    p = run([XDYNA, "--check", "i=" + os.path.join(ROOT, "input_decks/verify/bar_impact.k")], cwd=here)
    record("--check validates, prints the summary, writes nothing", p.returncode == 0 and "m o d e l" in p.stdout
           and os.listdir(here) == [], p.stdout[-200:] + p.stderr[-200:])
    p = run([XDYNA, "i=no_such_deck.k", "outdir=" + os.path.join(TMP, "nodeck")])
    record("a missing deck is an input error (exit 1)", p.returncode == 1 and "no_such_deck.k" in p.stderr)
    p = run([XDYNA, "i=x.k", "bogus=1"])
    record("an unknown argument is an input error (exit 1)", p.returncode == 1 and "bogus" in p.stderr)
    # the decomposition a run on 4 MPI ranks makes (issue 8): the paper's
    # frame's shells by cost (rigid parts' elements are no rank's work);
    # every rank within 2% of the mean cost (RCB cuts off by at most half an
    # element's cost), and a halo that is a small share of the nodes (compact
    # parts)
    p = run([XDYNA, "--check", "i=" + os.path.join(ROOT, "input_decks/paper/front_frame.k"), "parts=4"], cwd=here)
    m = re.search(r"largest cost / mean\s+([0-9.]+); nodes on rank boundaries (\d+) of (\d+)", p.stdout)
    rows = re.findall(r"^\s+(\d)\s+([0-9.]+)\s+([0-9.]+)\s+(\d+)\s+[\d ]+$", p.stdout, re.M)
    ok = p.returncode == 0 and m is not None and len(rows) == 4
    if ok:
        imb, halo, nn = float(m.group(1)), int(m.group(2)), int(m.group(3))
        ok = imb <= 1.02 and 0 < halo < 0.2 * nn and all(float(r[2]) >= 0.98 for r in rows)
    record("--check parts=4: the frame's decomposition, every part within 2% of the mean cost, halo under 20% of "
           "the nodes" + (f" ({m.group(1)}, {m.group(2)} of {m.group(3)})" if m else ""), ok, p.stdout[-400:])
    p = run([XDYNA, "--check", "i=x.k", "parts=0"])
    record("parts=0 is an input error (exit 1)", p.returncode == 1 and "parts=0" in p.stderr)


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
        q = mpirun(4, ["i=" + deck, "outdir=" + out, "endcyc=2"])
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


def contact_dump(out):
    """Blocks of contact_debug: (search, cycle, time, slave id, z, [(master id, trackable)])."""
    blocks = []
    for line in open(os.path.join(out, "contact_debug")):
        w = line.split()
        if w[0] == "search":
            blocks.append((int(w[1]), int(w[5]), float(w[7]), int(w[9]), float(w[13]), []))
        else:
            blocks[-1][5].append((int(w[0]), w[1] == "T"))
    return blocks


def interface_line(log, field):
    """Numbers of the summary row of the first interface: id, slaves,
    searches, masters/slave, pool/slave, reduced/slave, seconds, ns, max 4u/delta."""
    lines = log.split("c o n t a c t   s e a r c h   s u m m a r y")[1].splitlines()
    return [float(v) for v in lines[2].split()][field]


def test_contact_surface_log():
    """Every contact keyword runs the automatic algorithm on the parts its
    SSID/MSID select. Cube (2x2x2 hexahedra: 24 exterior faces, 26 surface
    nodes) over a plate (10x10 shells: 100 segments, 121 nodes): the log's
    counts follow from the selection by hand."""
    cases = {  # deck: (segments, shell, solid, surface nodes, slave nodes)
        "search_adaptive": (124, 100, 24, 147, 147),          # single surface, whole model
        "variant_surface_to_surface": (124, 100, 24, 147, 147),  # both sides are slaves
        "variant_nodes_to_surface": (100, 100, 0, 130, 9),     # 9 nodes of the cube's lower face
        "variant_segment_and_shell_sets": (104, 100, 4, 130, 130),  # cube's 4 lower faces vs shell set
        "variant_general_part_set": (24, 0, 24, 26, 26),       # part set {cube}
        "variant_single_all_but": (100, 100, 0, 121, 121),     # all but part set {cube}
    }
    for name, want in cases.items():
        p, out = run_deck(f"input_decks/contact/{name}.k", "contact_" + name)
        ok = p.returncode == 0
        got = None
        if ok:
            log = open(os.path.join(out, "d3hsp")).read()
            m = re.search(r"segments (\d+) \(shell (\d+), solid (\d+)\)\s+surface nodes (\d+)\s+slave nodes (\d+)", log)
            got = tuple(int(v) for v in m.groups()) if m else None
            ok = got == want and "contact ................... on" in log
        record(f"contact {name}: runs, log counts segments/shell/solid/nodes/slaves {want}", ok,
               f"got {got} {p.stderr[-200:]}")
    # SSTHK (*CONTROL_CONTACT card 2): a single-surface contact's shell
    # thickness is limited to 40% of the element's shortest edge (LS-DYNA's
    # default, SSTHK 0) unless SSTHK 1: the folding strip (5 mm elements)
    # made 4 mm thick has segments 2 mm thick for the contact, every shell
    # node named in the log; with SSTHK 1, 4 mm and no such line
    text = open(os.path.join(ROOT, "input_decks/contact/shell_fold.k")).read()
    assert "     0.001     0.001     0.001     0.001" in text
    text = text.replace("     0.001     0.001     0.001     0.001", "     0.004     0.004     0.004     0.004")
    for ssthk, tmax in ((0, 2.0e-3), (1, 4.0e-3)):
        deck = os.path.join(TMP, f"contact_ssthk{ssthk}.k")
        with open(deck, "w") as fh:
            fh.write(text.replace("*END", "*CONTROL_CONTACT\n" + "%10d" * 8 % (0, 0, 0, 0, 0, 0, 0, 0) + "\n" +
                                  "%10d" * 6 % (0, 0, 0, 0, 0, ssthk) + "\n*END"))
        out = os.path.join(TMP, f"contact_ssthk{ssthk}")
        p = run([XDYNA, "i=" + deck, "outdir=" + out, "endtim=1e-6"])
        log = open(os.path.join(out, "d3hsp")).read() if p.returncode == 0 else ""
        m = re.search(r"segment thickness min/max\s+(\S+)\s+(\S+)", log)
        got = float(m.group(2)) if m else float("nan")
        named = re.search(r"limited to 40% of the shortest edge at (\d+) nodes", log)
        nshell_nodes = len(re.findall(r"^\s*\d+\s+\S+e[-+]\d+\s", text.split("*NODE")[1].split("*")[0], re.M))
        want_named = (named is not None and int(named.group(1)) == nshell_nodes) if ssthk == 0 else named is None
        record(f"contact SSTHK {ssthk}: a 4 mm strip of 5 mm shells has contact thickness {got * 1e3:.2f} mm "
               f"(expected {tmax * 1e3:.1f}); the limit named for every node ({named.group(1) if named else 0} of "
               f"{nshell_nodes}) only where it applies", abs(got - tmax) < 1e-12 and want_named, p.stderr[-300:])
    # MBOXID: only the plate's shells whose centre lies in a box over x <= 0.5
    # (5 columns of 10) are master segments: 24 + 50 segments, 26 + 66 nodes
    text = open(os.path.join(ROOT, "input_decks/contact/variant_surface_to_surface.k")).read()
    old = "         7cube on plate\n         1         2         3         3\n"
    assert old in text
    deck = os.path.join(TMP, "contact_mboxid.k")
    with open(deck, "w") as fh:
        fh.write(text.replace(old, "         7cube on plate\n         1         2         3         3         0         9\n")
                 .replace("*KEYWORD\n", "*KEYWORD\n*DEFINE_BOX\n         9      -1.0       0.5      -1.0       2.0      -1.0       0.1\n", 1))
    p, out = run_deck(deck, "contact_mboxid")
    got = None
    if p.returncode == 0:
        m = re.search(r"segments (\d+) \(shell (\d+), solid (\d+)\)\s+surface nodes (\d+)\s+slave nodes (\d+)",
                      open(os.path.join(out, "d3hsp")).read())
        got = tuple(int(v) for v in m.groups()) if m else None
    record(f"contact MBOXID: only the master segments centred in the box (log counts {got}, expected "
           f"(74, 50, 24, 92, 92))", got == (74, 50, 24, 92, 92), p.stderr[-200:])
    log = open(os.path.join(TMP, "contact_variant_single_all_but", "d3hsp")).read()
    record("contact: card A BSORT 5 sets the search interval of its interface",
           "global search every 5 cycles" in log)


def test_contact_search_interval():
    """The cube falls at 200 m/s onto the plate.
    Adaptive interval: the plate node under the slave must be in its master
    node list at the first search where the slave is within reach of the
    plate, i.e. before the slave's contact surface touches the plate's
    (bound: zero penetration before detection). Every cycle must have used
    lists with 4u <= delta (the guarantee). A fixed interval of 170 cycles
    is the longest interval: searches still run whenever 4u > delta, and
    the same two bounds hold (issue 16; before it, the plate entered a list
    only after the cube had passed through)."""
    half_t = 0.005  # plate half-thickness (m)
    for name in ("search_adaptive", "search_fixed_170"):
        p, out = run_deck(f"input_decks/contact/{name}.k", "contact_" + name)
        if p.returncode != 0:
            record(f"contact {name} runs", False, p.stderr[-300:])
            continue
        blocks = contact_dump(out)
        found = [b for b in blocks if any(m >= 1001 for m, _ in b[5])]
        gap = found[0][4] - half_t if found else float("nan")
        worst = interface_line(open(os.path.join(out, "d3hsp")).read(), 8)
        if name == "search_adaptive":
            record(f"contact adaptive search: plate found {gap * 1e3:.1f} mm before touching "
                   f"(bound: > 0), after {found[0][0] if found else 0} searches", gap > 0 and len(blocks) > 5)
            trk = [t for m, t in found[0][5] if m >= 1001] if found else []
            record("contact adaptive search: the plate's closest node is a trackable master "
                   "(an opposite region, one node)", trk == [True])
            record(f"contact adaptive search: every cycle used lists with 4u/delta <= 1 ({worst:.3f})",
                   worst <= 1.0)
        else:
            # the fixed interval is the longest one: a search also runs when
            # 4u > delta, so the plate is found in time as with the adaptive
            # policy (before issue 16 it entered a list only after the cube
            # had passed it, with 4u/delta = 24)
            record(f"contact fixed interval 170 keeps the bound: plate found {gap * 1e3:.1f} mm before "
                   f"touching (> 0); every cycle used lists with 4u/delta <= 1 ({worst:.3f})",
                   bool(found) and gap > 0 and worst <= 1.0)
    # the default (SEARCH 0, no interval in the deck) searches on the motion
    # alone, as SEARCH 2 does: the same searches at the same cycles, so the
    # same run bit for bit (before 2026-11-26 it also searched every 100
    # cycles: more searches, the same bound)
    pd, outd = run_deck("input_decks/contact/search_default.k", "contact_search_default")
    outa = os.path.join(TMP, "contact_search_adaptive")
    if pd.returncode != 0 or not os.path.exists(os.path.join(outa, "thist.h5")):
        record("contact default search runs", False, pd.stderr[-300:])
        return
    logd = open(os.path.join(outd, "d3hsp")).read()
    nd, na = interface_line(logd, 2), interface_line(open(os.path.join(outa, "d3hsp")).read(), 2)
    same = all(np.array_equal(glstat(outd)[k], glstat(outa)[k]) for k in glstat(outa))
    record(f"contact default search: on the motion alone, named in d3hsp; {nd:.0f} searches as the adaptive "
           f"policy's {na:.0f}, every cycle within the bound (4u/delta {interface_line(logd, 8):.3f} <= 1), "
           f"glstat bitwise the adaptive run's",
           "global search on the motion alone" in logd and nd == na and interface_line(logd, 8) <= 1.0 and same)


def test_contact_fine_patch_classes():
    """A fine patch meeting a coarse plate (issue 28, deliverable 7): a 2 mm
    square of 8 x 8 shells of 0.25 mm falls at 10 m/s from 1 mm onto a free
    20 mm plate of 10 x 10 shells of 2 mm, both 0.1 mm thick, single
    surface. The
    pool margins follow the local size (0.5 times each node's length, the
    plate's nodes the majority), so the patch's slaves are a margin class of
    their own, searched at their own pace, and the plate's at theirs. Held to
    what the search's bound promises: d3hsp names two margin classes and
    searches of some classes only; every cycle within its margins (max
    4u/delta <= 1); no missed contact allowed and no pass-through (the
    independent checker, overlap under half the thickness); the contact
    creates no energy (sliding energy not below -1e-3 of the initial kinetic
    energy, the suite's band); the patch leaves upward (it bounced)."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import contact_suite as cs
    import penetration
    t, v = 1.0e-4, 10.0
    gap = 1.0e-3      # the patch falls through many of its own margins first
    A = cs.shell_grid(cs.lin(0, 0.02, 10), cs.lin(0, 0.02, 10), lambda a, b: (a, b, 0.0))
    B = cs.shell_grid(cs.lin(0.009, 0.011, 8), cs.lin(0.009, 0.011, 8), lambda a, b: (a, b, gap))
    T = (gap - t) / v + 2.0 * cs.spring_time(cs.RHO * t * 4.0e-6, 2.5e-4, 4.0e-6)
    c = {"name": "fine_patch_classes"}
    lines = cs.deck(c, [A, B], [("el", t), ("el", t)], [(0, 0, 0), (0, 0, -v)], 1.5 * T, ("single", False))
    out = os.path.join(TMP, "contact_fine_patch_classes")
    os.makedirs(out, exist_ok=True)
    cs.g.write(os.path.join(out, "deck.k"), lines)
    p = run([XDYNA, "i=deck.k"], cwd=out)
    if p.returncode != 0:
        record("contact fine patch on a coarse plate runs", False, p.stderr[-300:])
        return
    log = open(os.path.join(out, "d3hsp")).read()
    m = re.search(r"(\d+) margin classes", log)
    ncls = int(m.group(1)) if m else 0
    m = re.search(r": (\d+) of the (\d+) searches of some margin classes only", log)
    npart, nsearch = (int(m.group(1)), int(m.group(2))) if m else (0, 0)
    worst = interface_line(log, 8)
    missed = len(re.findall(r"missed contact \(entered since the search\)", log))
    over, cross, _, _ = penetration.check_run(out)
    e = glstat(out)
    created = max(0.0, -e["sliding_interface_energy"].min()) / e["kinetic_energy"][0]
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        vz = f["matsum/z_momentum"][-1, 1] / f["matsum/mass"][-1, 1]
    record(f"contact: a fine patch on a coarse plate, searched by margin class ({ncls} classes, {npart} of "
           f"{nsearch} searches of some classes only): 4u/delta {worst:.3f} <= 1, {missed} missed contacts, "
           f"{cross} pass-throughs, overlap {over:.2f} of the thickness (< 0.5), energy created {created:.1e} "
           f"(<= 1e-3), the patch leaves at {vz:+.2f} m/s (> 0)",
           ncls >= 2 and npart > 0 and worst <= 1.0 and missed == 0 and cross == 0 and over < 0.5
           and created <= 1e-3 and vz > 0)


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


def test_lagrange_step():
    """The Lagrangian projection has no springs, so no contact time-step
    bound (issue 28, deliverable 6): an elastic cube of 2 x 2 x 2
    hexahedra dropped at 10 m/s onto a fixed rigid block with the
    projection (the contact suite's corner_on_face k2 rotx0 case) runs at
    its elements' step (d3hsp: the contact springs' bound set it in 0
    cycles, and no warning that the contact sets the step) and to its end:
    the block's corner node rings in the mesh's highest mode, and a step
    that follows that ringing (shorter in the cycles the element
    compresses: the bulk viscosity's linear term) pumped it until the run
    stopped at cycle 479; the step now grows by 0.1% a cycle at most, and
    d3hsp counts the cycles that limit held it. Bands: the suite's own for
    the case (the cube bounces off, the energy ratio within 5%, no
    pass-through, overlap under half the window), and the same cube with
    penalty contact still bound (its springs set the step)."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import contact_suite as cs
    cs.OUT = os.path.join(TMP, "lagrange_step")
    sel = {c["name"]: c for c in cs.cases()}
    for name, lag in (("corner_on_face_single_lag_node_1to1_k2_v10_rotx0", True),
                      ("corner_on_face_single_pen_node_1to1_k2_v10_rotx0", False)):
        r = cs.run_case(sel[name])
        log = open(os.path.join(cs.OUT, name, "d3hsp")).read() if r["rc"] == 0 else ""
        m = re.search(r"by the contact springs' bound in (\d+) cycles.*held to 0\.1% growth a cycle in (\d+) cycles", log)
        bound = int(m.group(1)) if m else -1
        held = int(m.group(2)) if m else -1
        warned = "the contact sets the time step" in log
        if lag:
            record(f"contact: the Lagrangian projection runs at its elements' step, not the contact's bound (set by the "
                   f"bound in {bound} cycles, warned {warned}), to the end of a cube's corner impact ({r['answer']}: "
                   f"{'pass' if not r['fails'] else '; '.join(r['fails'])}); step held by the 0.1% growth limit in "
                   f"{held} cycles", r["rc"] == 0 and not r["fails"] and bound == 0 and not warned and held >= 0,
                   f"rc {r['rc']}")
        else:
            record(f"contact: the same cube with penalty contact keeps the springs' bound (set by it in {bound} cycles)",
                   r["rc"] == 0 and not r["fails"] and bound > 0, f"rc {r['rc']}")


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


def test_initial_penetration():
    """The edge-on plate starting 0.5 mm into the block with its
    half-thickness, under the three IGNORE rules of *CONTROL_CONTACT.
    IGNORE 1: the initial penetration is allowed and shrinks as the nodes
    move out, so no spring energy is injected: energy ratio within 1e-3 (a
    penalty force on it would throw the 25 g plate out with 66 J, ratio 33),
    the log names it, the plate still bounces off the face. IGNORE 0
    (LS-DYNA's default, no card): the nine edge nodes are moved out along
    the face normal by their depth before the run (d3hsp names each with
    both coordinates; 0.5 mm within 0.5 nm plus the hair beyond the surface
    the move adds, 1e-6 of the window), nothing is left to allow, and the same energy and bounce
    hold. IGNORE 2: nothing moved, each node named with the coordinates that
    would remove it, the same as IGNORE 0's moves (to 1e-8 m: the moves go
    a hair, 1e-6 of the window, beyond the surface)."""
    deck = "input_decks/contact/shell_edge_initially_penetrating.k"
    runs = {}
    for ig in (0, 1, 2):
        src = deck if ig == 0 else with_cards(deck, f"shell_edge_pen_ig{ig}",
                                              "*CONTROL_CONTACT\n0.1\n\n\n" f"{ig}\n")
        p, out = run_deck(src, f"shell_edge_pen_ig{ig}")
        if p.returncode != 0:
            record(f"initially penetrating plate runs (IGNORE {ig})", False, p.stderr[-300:])
            return
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            ratio = f["glstat/energy_ratio"][:]
            vz = f["matsum/z_momentum"][:, 1] / f["matsum/mass"][0, 1]
        runs[ig] = (np.max(abs(ratio - 1)), vz[-1], open(os.path.join(out, "d3hsp")).read())
    dev, vend, log = runs[1]
    record(f"initial penetration, IGNORE 1: allowed, no energy injected ({dev:.1e} within 1e-3), logged, plate bounces "
           f"({vend:+.2f} m/s)", dev < 1e-3 and "initial penetrations" in log and vend > 0.5)

    def moves(log, pat):
        got = {}
        for line in log.splitlines():
            m = re.search(r"node (\d+) initially inside segment[ 0-9]* by +([-+0-9.E]+)" + pat, line)
            if m:
                nums = [float(t) for t in re.findall(r"[-+]?\d\.\d+E[-+]\d+", line.split(":")[-1])]
                got[int(m.group(1))] = (float(m.group(2)), nums)
        return got
    dev, vend, log = runs[0]
    mv = {n: v for n, v in moves(log, r", moved out \(IGNORE 0\) by +(\S+)").items()}
    dz = [v[1][5] - v[1][2] for v in mv.values()]
    ok = (len(mv) == 9 and all(abs(d - 5e-4) < 1e-8 for d in dz)
          and all(abs(v[0] - 5e-4) < 1e-9 for v in mv.values()) and "initial penetrations (deepest" not in log)
    record(f"initial penetration, IGNORE 0 (default): {len(mv)} edge nodes moved out by "
           f"{min(dz) * 1e3:.6f}-{max(dz) * 1e3:.6f} mm (0.5 mm), none left to allow, energy {dev:.1e} within 1e-3, "
           f"plate bounces ({vend:+.2f} m/s)", ok and dev < 1e-3 and vend > 0.5)
    dev2, vend2, log2 = runs[2]
    rec = moves(log2, r".*\(IGNORE 2, tracked\)")
    # (the moves go a hair, 1e-6 of the 8 mm window, beyond the surface: 8 nm)
    same = len(rec) == 9 and all(n in mv and max(abs(a - b) for a, b in zip(rec[n][1][3:], mv[n][1][3:])) < 1e-8
                                 for n in rec)
    record(f"initial penetration, IGNORE 2: {len(rec)} nodes named with the coordinates that remove them (IGNORE 0's "
           f"moves, within 1e-8 m), tracked as IGNORE 1 (energy {dev2:.1e})",
           same and "initial penetrations (deepest" in log2 and dev2 < 1e-3)


def plates_deck(path, v, penmax=None):
    """A 10 mm square plate (5 x 5 shells, 1 mm) thrown flat at v m/s onto a
    plate below it held at every node, offset 0.3 mm in x and y so that
    each plate's nodes lie inside the other's segments; one single-surface
    contact (SSTHK 0: thickness 0.8 mm, 40% of the 2 mm edge), with PENMAX
    on optional card B if given."""
    n = 6
    lines = ["*KEYWORD", "*TITLE", "a plate thrown flat onto a held plate", "*CONTROL_TERMINATION", "  4.0e-5",
             "*CONTROL_TIMESTEP", "         0       0.9", "*DATABASE_GLSTAT", "  1.0e-7", "*DATABASE_NODOUT", "  1.0e-7",
             "*SECTION_SHELL", "         1         2         1         3", "     0.001     0.001     0.001     0.001",
             "*MAT_ELASTIC", "         1      7850 2.000e+11       0.3",
             "*PART", "held", "         1         1         1", "*PART", "thrown", "         2         1         1",
             "*NODE"]
    held, held_e = shell_grid(n, 1, 1, 0)
    thrown, thrown_e = shell_grid(n, 101, 2, len(held_e), shift=0.3e-3, z=1.05e-3)
    lines += held + thrown + ["*ELEMENT_SHELL"] + held_e + thrown_e
    lines += node_set(1, list(range(1, 1 + n * n))) + node_set(2, list(range(101, 101 + n * n)))
    lines += ["*BOUNDARY_SPC_SET", "         1         0         1         1         1         1         1         1",
              "*INITIAL_VELOCITY", "         2", f"         0         0{-v:10.4g}",
              "*DATABASE_HISTORY_NODE", "       115       122",
              "*CONTACT_AUTOMATIC_SINGLE_SURFACE", "         0", "0.0", "0.0"]
    if penmax is not None:
        lines += ["         0", f"{penmax:10.4g}"]
    lines.append("*END")
    return write_lines(path, lines)


def test_penmax():
    """PENMAX of *CONTACT optional card B: a contact deeper than PENMAX times
    the segment's thickness is released. The plate thrown at 200 m/s onto
    the held plate sinks about 0.16 mm into the 0.8 mm contact thickness
    (0.2 of it): without PENMAX (xdyna's zone: to the mid-surface) and with
    PENMAX 0.4 (LS-DYNA's default) it is held and thrown back (upward speed
    at the end); with PENMAX 0.1 every contact is released past 0.08 mm
    (each named in d3hsp with a depth above that limit) and the plate
    passes through (both history nodes end below the held plate). The
    energy ratio stays within 1e-3 in all three: a release removes a
    spring's force, never adds energy."""
    res = {}
    for tag, pm in (("none", None), ("0.4", 0.4), ("0.1", 0.1)):
        deck = plates_deck(os.path.join(TMP, f"plates_pm{tag}.k"), 200.0, pm)
        p, out = run_deck(deck, f"plates_pm{tag}")
        if p.returncode != 0:
            record(f"PENMAX {tag}: plate impact runs", False, p.stderr[-300:])
            return
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            z = f["nodout/z_coordinate"][:]
            vz = f["nodout/z_velocity"][-1].mean()
            ratio = f["glstat/energy_ratio"][:]
        log = open(os.path.join(out, "d3hsp")).read()
        depths = [float(x) for x in re.findall(r"released beyond PENMAX.*depth +(\S+)", log)]
        res[tag] = (z, np.max(abs(ratio - 1)), depths, vz)
    for tag in ("none", "0.4"):
        z, dev, depths, vz_end = res[tag]
        record(f"PENMAX {tag}: the thrown plate is held (deepest {(0.8e-3 - z.min()) * 1e3:.3f} mm into 0.8 mm) and "
               f"thrown back ({vz_end:+.0f} m/s), none released, energy {dev:.1e} within 1e-3",
               z.min() > 0.4e-3 and vz_end > 0 and not depths and dev < 1e-3)
    z, dev, depths, _ = res["0.1"]
    record(f"PENMAX 0.1: {len(depths)} contacts released past 0.08 mm (named depths {min(depths or [0]) * 1e3:.4f}-"
           f"{max(depths or [0]) * 1e3:.4f} mm), the plate passes through (ends at z {z[-1].max() * 1e3:+.2f} mm), "
           f"energy {dev:.1e} within 1e-3",
           len(depths) >= 36 and min(depths) > 0.08e-3 and z[-1].max() < 0 and dev < 1e-3)


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


def test_tube_crush(full=False):
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


def test_near_sets_exact():
    """The local search's shortcuts give the general search's results, bit
    for bit: the clearance skip, the near sets (a slave whose fresh
    clearance leaves its nearest segments out is checked against them
    alone, and searched in full only where one finds or refuses a
    contact) and the tetrahedron screens. The tube crush's first 2 ms
    (folds forming, nodes lying near segments they do not touch) with the
    screens on and with SCREEN 2 of *CONTROL_XDYNA_CONTACT (every slave
    searched in full every cycle): glstat and nodout the same bit for bit
    (no tolerance: the shortcuts only leave out checks that find nothing),
    and the first run's d3hsp counts its near-set checks (more than 1,000:
    the path is taken)."""
    deck = os.path.join(ROOT, "input_decks/contact/tube_crush.k")
    p1, out1 = run_deck("input_decks/contact/tube_crush.k", "near_sets_on", extra=("endtim=2.0e-3",))
    text = ("*KEYWORD\n*CONTROL_XDYNA_CONTACT\n"
            "         0         0         0         0         2         0         0         0\n"
            f"*INCLUDE\n{deck}\n*END\n")
    path = os.path.join(TMP, "near_sets_off.k")
    with open(path, "w") as f:
        f.write(text)
    out2 = os.path.join(TMP, "near_sets_off")
    shutil.rmtree(out2, ignore_errors=True)
    p2 = run([XDYNA, "i=" + path, "outdir=" + out2, "endtim=2.0e-3"])
    if p1.returncode != 0 or p2.returncode != 0:
        record("near sets: the tube crush runs with the screens on and off", False, (p1.stderr + p2.stderr)[-300:])
        return
    log = open(os.path.join(out1, "d3hsp")).read()
    m = re.search(r": (\d+) slave-cycles checked by their near sets alone \(.*?\), (\d+) of them searched in full", log)
    nn, nf = (int(m.group(1)), int(m.group(2))) if m else (0, 0)
    same = True
    with h5py.File(os.path.join(out1, "thist.h5"), "r") as a, h5py.File(os.path.join(out2, "thist.h5"), "r") as b:
        for g in ("glstat", "nodout"):
            for k in a[g]:
                same = same and np.array_equal(a[g][k][()], b[g][k][()])
    off_log = open(os.path.join(out2, "d3hsp")).read()
    record(f"near sets: the tube crush's first 2 ms, screens on ({nn} near-set checks, {nf} then searched in full) "
           f"and off (every slave searched every cycle): glstat and nodout bitwise the same",
           same and nn > 1000 and "near sets alone" not in off_log)


def test_penetration_checker():
    """The penetration checker (tools/penetration.py) measured on made-up
    states, so that the checks that lean on it can fail: a node pushed
    3 mm into a 10 mm hexahedron through its top face must read 0.3 of the
    element's depth (its depth below the nearest exterior face); 2 mm
    inside a side face and 4 mm below the top must read 0.2 (the nearest
    face); outside, 0. A node of a 2 mm shell 1.5 mm
    from another 2 mm shell's mid-surface overlaps (2 + 2)/2 - 1.5 = 0.5 mm,
    0.25 of the thickness; moved through to the other side between two
    states it is one pass-through."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import penetration as pen
    h = 0.01
    cube = np.array([[0, 0, 0], [h, 0, 0], [h, h, 0], [0, h, 0], [0, 0, h], [h, 0, h], [h, h, h], [0, h, h]], float)
    for label, p, want in (("through the top face", [0.005, 0.005, h - 0.003], 0.3),
                           ("near an edge, through a side face", [h - 0.002, 0.005, h - 0.004], 0.2),
                           ("outside", [0.005, 0.005, h + 0.001], 0.0)):
        X = np.vstack([cube, [p]])[None]                 # the ninth node belongs to no element
        surf = pen.Surfaces(9, [], [], [list(range(8))], [1])
        worst, _ = pen.check_states(surf, X, np.zeros((1, 0)), np.arange(1, 10))
        record(f"penetration checker: a node {label} reads {worst:.3f} of the element depth (expected {want})",
               abs(worst - want) < 1e-9)
    sq = [[0, 0, 0], [h, 0, 0], [h, h, 0], [0, h, 0]]
    def two_shells(z):
        other = [[0.002, 0.002, z], [0.008, 0.002, z], [0.008, 0.008, z], [0.002, 0.008, z]]
        return np.array(sq + other, float)
    surf = pen.Surfaces(8, [[0, 1, 2, 3], [4, 5, 6, 7]], [1, 2])
    X = np.array([two_shells(0.0015), two_shells(-0.0015)])
    worst, crossings = pen.check_states(surf, X, np.full((2, 2), 0.002), np.arange(1, 9))
    record(f"penetration checker: shells 1.5 mm apart overlap {worst:.3f} of the thickness (expected 0.25); "
           f"crossing between two states is {crossings} pass-through(s) (expected 4: the four corners)",
           abs(worst - 0.25) < 1e-9 and crossings == 4)
    # a triangle (N3 = N4) and a lone node (no thickness of its own) in its
    # plane 2 mm beyond its long edge, then 0.5 mm above its inside: 0 (the
    # projection is outside), then (0 + 2)/2 - 0.5 = 0.5 mm, 0.25 of its
    # 2 mm (the degenerate bilinear patch once read a full overlap beside a
    # triangle)
    tri = [[0, 0, 0], [h, 0, 0], [0, h, 0]]
    for label, p, want in (("beside a triangle, in its plane", [0.007, 0.007, 0.0], 0.0),
                           ("0.5 mm above a triangle", [0.002, 0.002, 0.0005], 0.25)):
        X = np.array([tri + [p]], float)
        surf = pen.Surfaces(4, [[0, 1, 2, 2]], [1])
        worst, _ = pen.check_states(surf, X, np.full((1, 1), 0.002), np.arange(1, 5))
        record(f"penetration checker: a node {label} reads {worst:.3f} of the thickness (expected {want})",
               abs(worst - want) < 1e-9)
    # the same crossing where the shell it crosses has eroded by the second
    # state (d3plot's deletion flags): no pass-through
    X = np.array([two_shells(0.0015), two_shells(-0.0015)])
    _, gone = pen.check_states(pen.Surfaces(8, [[0, 1, 2, 3], [4, 5, 6, 7]], [1, 2]), X, np.full((2, 2), 0.002),
                               np.arange(1, 9),
                               alive_states=np.array([[1.0, 1.0], [0.0, 1.0]]))
    record(f"penetration checker: a node crossing where an eroded shell was is no pass-through ({gone}, expected 0; "
           f"with the shell alive: {crossings})", gone == 0 and crossings == 4)
    # a node beside a segment in the plane of its free edge (the demo tube's
    # top ring, two states 0.1 ms apart under the viscous form): the
    # closest point on the bilinear patch leaps from one side to the other
    # (+6.3 mm, then -4.0 mm, both read inside) while the node and the
    # segment move 1.4 mm at most; a node that went through would have
    # changed its distance by no more than that: no pass-through
    X = 1e-3 * np.array([[[-8.8779, -10.5248, 121.2078], [-5.0182, -10.9676, 118.5543],
                          [-4.6443, -5.3616, 122.9992], [-2.3313, -15.2005, 122.9992],
                          [-8.0903, -14.9293, 122.9992]],
                         [[-8.8674, -10.4571, 120.2693], [-5.026, -11.1037, 117.667],
                          [-4.6469, -5.2688, 121.9988], [-2.0778, -15.3152, 121.9988],
                          [-8.0077, -14.9226, 121.9988]]])
    bd, bin_ = pen.bilinear_distance(X[:, 4], X[:, 0:4])
    surf = pen.Surfaces(5, [[0, 1, 2, 3]], [1])
    _, crossings = pen.check_states(surf, X, np.full((2, 1), 0.0015), np.arange(1, 6))
    record(f"penetration checker: a node in the plane of a free edge whose closest point leaps sides "
           f"({bd[0] * 1e3:+.1f} then {bd[1] * 1e3:+.1f} mm, moving at most 1.4 mm) is no pass-through "
           f"({crossings}, expected 0)", crossings == 0 and bd[0] > 0.005 and bd[1] < -0.003 and bin_.all())
    # --growth: a node that starts in a shell's plane (a part meeting another
    # in its plane, as public decks have) and jitters about it is no
    # pass-through, and its overlap (0.5 of the thickness from the start)
    # does not grow; without --growth the same states read 0.5 and 2
    X = np.array([tri + [[0.002, 0.002, z]] for z in (0.0, 1e-4, -1e-4, 1e-4)], float)
    surf = pen.Surfaces(4, [[0, 1, 2, 2]], [1])
    T = np.full((4, 1), 0.002)
    worst, crossings = pen.check_states(surf, X, T, np.arange(1, 5), growth=True)
    worst0, crossings0 = pen.check_states(surf, X, T, np.arange(1, 5))
    record(f"penetration checker --growth: a node jittering in a shell's plane from the start: overlap growth "
           f"{worst:.3f}, pass-throughs {crossings} (expected 0, 0; plain: {worst0:.3f}, {crossings0}, expected "
           f"0.5, 2)", abs(worst) < 1e-9 and crossings == 0 and abs(worst0 - 0.5) < 1e-9 and crossings0 == 2)


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


REFERENCE_OUTPUT = os.environ.get("XDYNA_REFERENCE_OUTPUT",
                                  os.path.join(os.path.dirname(ROOT), "shared", "reference-output"))


def layout(line):
    """A line's layout: its text with every number (sign included) replaced
    by blanks ending in one '#' at its last column: fixed-column readers
    slice right-aligned fields, so a field's end column is what counts
    (a sign or a longer id may reach further left)."""
    return re.sub(r"[-+]?\d+\.\d+E[-+]\d+|[-+]?\d+\.\d+|\d+",
                  lambda m: " " * (len(m.group(0)) - 1) + "#", line.rstrip("\n")).rstrip()


def test_thist_metadata():
    """thist.h5 says what its numbers are: the root carries the title, the
    code and version, the date and the unit system; every column its
    dimension and, where the deck names its units (*CONTROL_UNITS), its
    unit (mm, s, mtrc_ton: forces in N, energies in N*mm, accelerations in
    mm/s^2); every ids dataset the kind of entity it numbers. A unit
    LS-DYNA does not know is refused naming the field. (Before, `units`
    held the dimension and nothing said the rest.)"""
    def attr(obj, name):
        v = obj.attrs.get(name)
        if v is None:
            return None
        v = v[0] if hasattr(v, "__len__") and not isinstance(v, (bytes, str)) else v
        return (v.decode() if isinstance(v, bytes) else str(v)).strip()
    base = open(os.path.join(ROOT, "input_decks/verify/bar_wall.k")).read()
    p, out = run_deck("input_decks/verify/bar_wall.k", "meta_plain")
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        root = {k: attr(f, k) for k in ("title", "code", "date", "unit_system")}
        ke = (attr(f["glstat/kinetic_energy"], "dimension"), attr(f["glstat/kinetic_energy"], "units"))
        ent = attr(f["rwforc/ids"], "entity")
    record(f"thist.h5 root: title, code, date, unit system ({root})", p.returncode == 0 and root["title"]
           and root["code"].startswith("xdyna ") and re.match(r"\d{4}-\d\d-\d\dT", root["date"] or "")
           and "not given" in root["unit_system"])
    record(f"thist.h5 without *CONTROL_UNITS: dimension 'energy', no unit claimed ({ke}); ids say what they "
           f"number ({ent!r})", ke == ("energy", "") and ent.startswith("rigid wall id"))
    deck = os.path.join(TMP, "meta_units.k")
    with open(deck, "w") as f:
        f.write(base.replace("*KEYWORD\n", "*KEYWORD\n*CONTROL_UNITS\n        mm       sec  mtrc_ton\n", 1))
    p = run([XDYNA, "i=" + deck, "outdir=" + os.path.join(TMP, "meta_units")])
    got = {}
    if p.returncode == 0:
        with h5py.File(os.path.join(TMP, "meta_units", "thist.h5"), "r") as f:
            got = {"energy": attr(f["glstat/kinetic_energy"], "units"), "force": attr(f["rwforc/x_force"], "units"),
                   "time": attr(f["glstat/time"], "units"), "system": attr(f, "unit_system")}
    record(f"thist.h5 with *CONTROL_UNITS mm sec mtrc_ton: units named ({got})", p.returncode == 0
           and got.get("energy") == "N*mm" and got.get("force") == "N" and got.get("time") == "s"
           and "force N" in got.get("system", ""), p.stderr[-300:])
    with open(deck, "w") as f:
        f.write(base.replace("*KEYWORD\n", "*KEYWORD\n*CONTROL_UNITS\n     parsec\n", 1))
    q = run([XDYNA, "--check", "i=" + deck])
    record("*CONTROL_UNITS: an unknown unit is refused naming the field and value",
           q.returncode == 1 and "LENGTH" in q.stderr and "parsec" in q.stderr, q.stderr[-300:])


def test_lstc_layouts():
    """nodout and rwforc in the layout of LSTC's binout-to-ASCII translator
    (no R14 nodout or rwforc is in ../shared/reference-output; its printf
    formats are the model): every nodout block after three blank lines, its
    header ' n o d a l ... s t e p%8d' + 30 blanks + '( at time%14.7E )',
    the step counted from 1 as glstat's; each row '%9d%13.4E' then
    '%12.4E' (12 values; with shells a second block of the same step with
    the rotations, 9 values); rwforc's column line after two blank lines and
    its rows '%12.5E%8d%15.6E%15.6E%15.6E%15.6E'. Every line is rebuilt from
    the numbers read off it with those formats and must come out the same,
    character for character. glstat's `dt of cycle` line: the cycle, element
    and part in the columns fixed-column readers slice (14-20, 45-53, 63-71,
    1-based). The rotation block holds physics: the warped shell patch
    spinning at 100 rad/s about x for a quarter turn reads x-rot = 100 t
    within 1e-3 of pi/2 and x-rot vel 100 within 1e-3 at every block."""
    deck = with_cards("input_decks/verify/shell_warped_spin.k", "lstc_spin",
                      "*DATABASE_NODOUT\n    0.0010\n*DATABASE_HISTORY_NODE\n         1         5\n")
    out = os.path.join(TMP, "lstc_spin")
    shutil.rmtree(out, ignore_errors=True)
    p = run([XDYNA, "i=" + deck, "outdir=" + out])
    record("LSTC layouts: the spinning shell runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return
    ls = open(os.path.join(out, "nodout")).read().splitlines()
    head = " n o d a l   p r i n t   o u t   f o r   t i m e  s t e p"
    cols = (" nodal point  x-disp     y-disp      z-disp      x-vel       y-vel       z-vel  "
            "    x-accl      y-accl      z-accl      x-coor      y-coor      z-coor")
    rcols = (" nodal point  x-rot      y-rot       z-rot       x-rot vel   y-rot vel   "
             "z-rot vel   x-rot acc   y-rot acc   z-rot acc")
    bad, nrow, nblock, rot, steps = [], 0, 0, [], []
    glines = [x for x in open(os.path.join(out, "glstat")).read().splitlines() if x.startswith(" dt of cycle")]
    gsteps = [int(x[13:20]) for x in glines]
    for i, x in enumerate(ls):
        if not x.startswith(head):
            continue
        nblock += 1
        step, t = int(x[len(head):len(head) + 8]), float(x.split("( at time")[1].split(")")[0])
        want = "%s%8d%s%14.7E )" % (head, step, "                              ( at time", t)
        if x != want or ls[i - 3:i] != ["", "", ""] or ls[i + 1] != "":
            bad.append((i, x))
        rotation = ls[i + 2] == rcols
        if not rotation:
            steps.append((step, t))
        if ls[i + 2] not in (cols, rcols):
            bad.append((i + 2, ls[i + 2]))
        k = i + 3
        while k < len(ls) and ls[k].strip():
            row = ls[k]
            v = [float(row[9:22])] + [float(row[22 + 12 * j:34 + 12 * j]) for j in range((8 if rotation else 11))]
            rebuilt = "%9d" % int(row[:9]) + "%13.4E" % v[0] + "".join("%12.4E" % a for a in v[1:])
            if rebuilt != row:
                bad.append((k, row, rebuilt))
            if rotation and int(row[:9]) == 5:
                rot.append((t, v[0], v[3]))
            nrow += 1
            k += 1
    # glstat counts the steps from 1; nodout's first block is step 1 at t = 0
    first_ok = bool(steps) and steps[0] == (1, 0.0) and bool(gsteps) and gsteps[0] == 1
    record(f"LSTC layouts: nodout, {nblock} blocks and {nrow} rows rebuilt character for character from LSTC's "
           f"formats, three blank lines before each block, the first step 1 at t = 0 (glstat's first "
           f"`dt of cycle` {gsteps[:1]})", not bad and nblock > 0 and first_ok and len(rot) > 0,
           f"first difference {bad[:1]}")
    err_a = max(abs(a - 100.0 * t) for t, a, w in rot) / (math.pi / 2) if rot else 1.0
    err_w = max(abs(w - 100.0) for t, a, w in rot) / 100.0 if rot else 1.0
    record(f"LSTC layouts: nodout rotation block, the spinning shell's node 5: x-rot = 100 t within 1e-3 of pi/2 "
           f"({err_a:.1e}, last {rot[-1][1] if rot else None:.5f} at t {rot[-1][0] if rot else 0:.5f}), x-rot vel "
           f"100 within 1e-3 ({err_w:.1e}), {len(rot)} blocks", err_a < 1e-3 and err_w < 1e-3 and len(rot) > 10)
    # glstat's dt of cycle line: the columns fixed-column readers slice
    ok = all(x[:12] == " dt of cycle" and x[13:20].strip().isdigit() and x[44:53].strip().isdigit()
             and x[62:71].strip().isdigit() and x[53:61] == " of part" for x in glines)
    record(f"LSTC layouts: glstat's {len(glines)} `dt of cycle` lines hold cycle, element and part in columns "
           f"14-20, 45-53, 63-71", ok and len(glines) > 0, glines[0] if glines else "")
    # rwforc
    p, out2 = run_deck("input_decks/verify/bar_heavy_wall.k", "lstc_rwforc")
    ls = open(os.path.join(out2, "rwforc")).read().splitlines() if p.returncode == 0 else []
    i = next((k for k, x in enumerate(ls) if x.startswith("    time       wall#")), None)
    bad, nrow = [], 0
    if i is not None:
        if ls[i - 3:i] != ["{END LEGEND}", "", ""] or \
                ls[i] != "    time       wall#   normal-force    x-force        y-force        z-force":
            bad.append((i, ls[i - 3:i + 1]))
        for row in ls[i + 1:]:
            v = [float(row[:12]), int(row[12:20])] + [float(row[20 + 15 * j:35 + 15 * j]) for j in range(4)]
            rebuilt = "%12.5E%8d" % (v[0], v[1]) + "".join("%15.6E" % a for a in v[2:])
            if rebuilt != row:
                bad.append(row)
            nrow += 1
    record(f"LSTC layouts: rwforc, the column line after two blank lines and {nrow} rows rebuilt character for "
           f"character from LSTC's format", i is not None and not bad and nrow > 10, f"first difference {bad[:1]}")


def test_ascii_layout():
    """glstat, matsum and rcforc in LS-DYNA R14's layout (issue 20): the
    files LS-DYNA R14 wrote in ../shared/reference-output are the model.
    A run of a deck with contact (a shell plate edge-on onto a block) is
    held to them line by line, every field in the same columns (a number
    by the column it ends in): the second header line
    (`date` and the date where readers look for them), the legend's frame,
    glstat's first block from the first `dt of cycle` line to the added
    mass (the line naming what controls the step names an element here,
    a load curve there: its first 20 columns), matsum's time line and one
    part's block, rcforc's SURFA and SURFB lines. thdiff reads the new
    rcforc's sides as the old slave and master (the reviewed references
    keep their names). SKIP where ../shared/reference-output is absent."""
    if not os.path.isdir(REFERENCE_OUTPUT):
        print("SKIP ASCII layout: ../shared/reference-output is not here")
        return
    p, out = run_deck("input_decks/contact/shell_edge_on_solid.k", "ascii_layout", extra=("endtim=2.0e-4",))
    record("ASCII layout: the deck runs (exit 0)", p.returncode == 0, p.stderr[-300:])
    if p.returncode != 0:
        return

    def lines(d, name):
        return open(os.path.join(d, name)).read().splitlines()

    def same(name, ours, ref, what):
        la, lb = [layout(x) for x in ours], [layout(x) for x in ref]
        bad = [(i, a, b) for i, (a, b) in enumerate(zip(la, lb)) if a != b]
        record(f"ASCII layout: {name} {what}: {len(lb)} lines as R14's, every field in its columns",
               len(la) == len(lb) and not bad, f"ours {len(la)} lines, R14 {len(lb)}; first difference "
               f"{bad[0] if bad else None}")

    for name in ("glstat", "matsum", "rcforc"):
        ours, ref = lines(out, name), lines(REFERENCE_OUTPUT, name)
        # the second header line: `date` at column 57, the date after it
        ok = ours[1].find(" date ") == ref[1].find(" date ") and len(ours[1].rstrip()) == len(ref[1].rstrip())
        record(f"ASCII layout: {name} header: the date in R14's columns", ok, f"{ours[1]!r} / {ref[1]!r}")
    # glstat: the first block, from its `dt of cycle` line to `percentage increase`
    ours, ref = lines(out, "glstat"), lines(REFERENCE_OUTPUT, "glstat")

    def block(ls):
        i = next((k for k, x in enumerate(ls) if x.startswith(" dt of cycle")), None)
        j = next((k for k, x in enumerate(ls) if x.startswith(" percentage increase")), None)
        if i is None or j is None:
            return ls[2:]          # not R14's block: compared whole, it differs
        return ls[2:i] + [ls[i][:20]] + ls[i + 1:j + 1]
    same("glstat", block(ours), block(ref), "first block")
    # matsum: legend frame, the first time line and the first part's block
    ours, ref = lines(out, "matsum"), lines(REFERENCE_OUTPUT, "matsum")

    def part_block(ls):
        i = next((k for k, x in enumerate(ls) if x.startswith(" time =")), 0)
        return [ls[i]] + ls[i + 1:i + 6]
    same("matsum", part_block(ours), part_block(ref), "time line and a part's block")
    frame = [x for x in ours if x.startswith(("{", " Entity #"))]
    record("ASCII layout: matsum legend frame as R14's", frame == [x for x in ref if x.startswith(("{", " Entity #"))],
           str(frame))
    # rcforc: the first SURFA and SURFB lines
    ours, ref = lines(out, "rcforc"), lines(REFERENCE_OUTPUT, "rcforc")
    pick = lambda ls: [next((x for x in ls if x.startswith("  SURFA")), ""),
                       next((x for x in ls if x.startswith("  SURFB")), "")]
    same("rcforc", pick(ours), pick(ref), "SURFA and SURFB lines")
    # no work is done by t = 0: a body driven by a prescribed motion from the
    # start reads external work 0 in glstat's first block (it read the first
    # half step's work while the total energy read 0), then grows
    p, out2 = run_deck("input_decks/verify/rigid_prescribed.k", "ascii_layout_work")
    ew = [float(x.split()[-1]) for x in lines(out2, "glstat") if x.startswith(" external work")] if p.returncode == 0 else []
    record(f"glstat: external work 0 at t = 0, then positive ({ew[:1]}, last {ew[-1:]})",
           len(ew) > 1 and ew[0] == 0.0 and ew[-1] > 0.0)
    sys.path.insert(0, os.path.join(ROOT, "src", "tools"))
    import thdiff as thd
    names = set(thd.load(os.path.join(out, "rcforc"), None))
    record("ASCII layout: thdiff reads R14's SURFA and SURFB as the slave and master sides",
           any(n.startswith("rcforc/slave-x") for n in names) and any(n.startswith("rcforc/master-x") for n in names),
           str(sorted(names)[:6]))


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
    g = run(["/usr/bin/python3", os.path.join(ROOT, "tools", "gen_decks.py"), "--bench-tubes", "10", "10", deck,
             "--cycles", "2"])
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


def test_public_forms():
    """Input forms of decks written by others (tests/decks/forms): *INCLUDE
    with several file cards and a name continued with ' +', *INCLUDE_PATH,
    *PARAMETER_EXPRESSION (thk = 1*2 + sqrt(|-4|)*0.5 - max(0, 1) + 1 = 3),
    *PARAMETER_LOCAL, *SET_NODE_GENERAL_TITLE (BOX + NODE - DNODE),
    *SET_PART_ADD, *SET_SHELL_GENERAL, *DEFINE_BOX, *RIGIDWALL_PLANAR_FORCES
    with BOXID, an infinite cylinder, *PART_INERTIA on a rigid part of
    zero-thickness shells, *ELEMENT_SHELL_THICKNESS of zeros; and LS-DYNA's
    command line: jobid=, o=, memory=, ncpu=-N. Masses are sums of the
    deck's numbers, exact but for float round-off: tolerance 1e-6."""
    out = os.path.join(TMP, "forms")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    printed = os.path.join(out, "printed.txt")
    p = run([XDYNA, "i=" + os.path.join(ROOT, "tests/decks/forms/main.k"), "outdir=" + out, "jobid=job",
             "o=" + printed, "memory=200m", "memory2=64000000", "ncpu=-1"])
    record("forms: the deck of public input forms runs (exit 0)", p.returncode == 0, p.stderr[-400:])
    if p.returncode != 0:
        return
    names = sorted(os.listdir(out))
    record("forms: jobid= prefixes every output file, o= names the printed output (" + " ".join(names) + ")",
           names == ["job.glstat", "job.matsum", "job.nodout", "job.rwforc", "job.thist.h5", "printed.txt"])
    log = open(printed).read()
    record("forms: memory= is accepted and named in d3hsp", "memory=200m accepted" in log)
    legend = open(os.path.join(out, "job.rwforc")).read()
    record("forms: _ID headings keep their commas (rwforc legend)", "floor under the plate, nodes of box 10 only"
           in legend and "post far away, infinite" in legend)
    with h5py.File(os.path.join(out, "job.thist.h5"), "r") as f:
        ids = list(f["matsum/ids"][:])
        mass = f["matsum/mass"][0]
        zmom = f["matsum/z_momentum"][0]
        vz = f["nodout/z_velocity"][:]
    plate = 7.85e-9 * 100.0 * 100.0 * 3.0        # rho x area x thk from the expression
    record(f"forms: plate mass = rho A thk with thk from *PARAMETER_EXPRESSION ({mass[ids.index(1)]:.6e} "
           f"against {plate:.6e})", abs(mass[ids.index(1)] / plate - 1) < 1e-6)
    record(f"forms: *PART_INERTIA mass 1e-3 and initial z momentum TM VTZ = -0.01 ({mass[ids.index(2)]:.6e}, "
           f"{zmom[ids.index(2)]:.6e})", abs(mass[ids.index(2)] / 1e-3 - 1) < 1e-6
           and abs(zmom[ids.index(2)] / -0.01 - 1) < 1e-6)
    # node 12 lies in box 10 (constrained through *SET_NODE_GENERAL); node
    # 11, taken away by DNODE, is free: both start at vz = 1
    record(f"forms: *SET_NODE_GENERAL BOX - DNODE: node 12 held (|vz| max {abs(vz[:, 1]).max():.2e}), "
           f"node 11 free (|vz| max {abs(vz[:, 0]).max():.2e})", abs(vz[:, 1]).max() == 0.0
           and abs(vz[:, 0]).max() > 0.5)
    # input errors of the new forms: exit 1 naming file, line, keyword, field
    cases = [
        ("*PARAMETER_EXPRESSION\nR     bad        1.0/(2.0-2.0)\n", "bad_expr", ["bad_expr.k:5",
         "*PARAMETER_EXPRESSION field EXPRESSION of 'bad'", "division by zero"]),
        ("*PARAMETER_EXPRESSION\nR     bad        2.0*undefined_name\n", "undef_expr",
         ["undef_expr.k:5", "parameter 'UNDEFINED_NAME' is not defined"]),
        ("*INCLUDE\nthere.k\nnot_there.k\n", "missing_include", ["missing_include.k:6", "not_there.k"]),
        ("*SET_NODE_GENERAL\n         7\nBOX             99\n", "missing_box", ["missing_box.k:6", "box 99"]),
        ("*DEFINE_COORDINATE_SYSTEM\n         5       0.0       0.0       0.0       1.0       1.0       0.0\n"
         "       0.0       1.0       0.0\n*BOUNDARY_SPC_NODE\n         1         5         1\n", "skewed_spc",
         ["skewed_spc.k:8", "*BOUNDARY_SPC field CID", "not along a global axis"]),
        ("*DEFINE_COORDINATE_NODES\n         5         1         1         1\n", "degenerate_axes",
         ["degenerate_axes.k:5", "coordinate system 5", "on one line"]),
    ]
    for text, name, expect in cases:
        d = os.path.join(out, "err")
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "there.k"), "w") as f:
            f.write("*KEYWORD\n*END\n")
        with open(os.path.join(d, name + ".k"), "w") as f:
            f.write("*KEYWORD\n*TITLE\nerror\n" + text + "*CONTROL_TERMINATION\n  1.0e-5\n*NODE\n"
                    "       1             0.0             0.0             0.0\n*END\n")
        q = run([XDYNA, "i=" + os.path.join(d, name + ".k"), "outdir=" + os.path.join(d, name)])
        record(f"forms: {name} exits 1 naming " + "; ".join(expect),
               q.returncode == 1 and all(e in q.stderr for e in expect), q.stderr[-300:])


PUBLIC = os.environ.get("XDYNA_PUBLIC_DECKS", os.path.join(os.path.dirname(ROOT), "shared", "public-decks"))


def public_figures(out, stdout):
    """Energy ratios of glstat, or of the progress lines where the deck asks
    for no glstat (car5: then only every 5 s of wall time), the
    post's x-force history (rwforc wall 2) and the mean x velocity of the
    deck's history nodes (nodout) from a run of a public car deck."""
    ratio = np.array([float(v) for v in re.findall(r"ratio\s+(\S+)", stdout)])
    with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
        if "glstat" in f:
            ratio = f["glstat/energy_ratio"][:]
        rw = f["rwforc"]
        ids = list(rw["ids"][:])
        fx = rw["x_force"][:, ids.index(2)]
        vx = f["nodout/x_velocity"][:].mean(axis=1)
    return ratio, fx, vx


def test_public_decks():
    """The public decks of ../shared/public-decks run unchanged: car5 and car6
    for their first 10 ms (the pole is struck at 1.9 and 4.4 ms; the full runs
    are `make public`), ball_plate to its end. Asserted: normal termination,
    energy ratio within 2% (the issue's), the post pushed back (its x-force
    on the car positive: the car runs towards -x), the body's x momentum
    falling. SKIP where the corpus is absent."""
    if not os.path.isdir(PUBLIC):
        print("SKIP public decks: ../shared/public-decks is not here")
        return
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    for deck, end in (("car5_main.k", "0.010"), ("car6_main.k", "0.010")):
        out = os.path.join(TMP, "public_" + deck[:-2])
        shutil.rmtree(out, ignore_errors=True)
        p = run([XDYNA, "i=" + os.path.join(PUBLIC, deck), "outdir=" + out, "endtim=" + end])
        record(f"public {deck}: runs unchanged to normal termination at {end} s", p.returncode == 0
               and "normal termination" in p.stdout, p.stderr[-300:])
        if p.returncode != 0:
            continue
        ratio, fx, px = public_figures(out, p.stdout)
        if len(ratio) < 10:
            # the deck asks for no glstat: the same deck included from a
            # wrapper that adds *DATABASE_GLSTAT, for the energy ratio
            wrap = os.path.join(TMP, "glstat_" + deck)
            with open(wrap, "w") as fh:
                fh.write("*KEYWORD\n*DATABASE_GLSTAT\n   1.0e-04\n*INCLUDE\n" + os.path.join(PUBLIC, deck) + "\n*END\n")
            q = run([XDYNA, "i=" + wrap, "outdir=" + out + "_glstat", "endtim=" + end])
            if q.returncode == 0:
                ratio = glstat(out + "_glstat")["energy_ratio"]
        dev = float(np.max(abs(ratio - 1)))
        record(f"public {deck}: energy ratio within 2% of 1 (largest deviation {dev:.1e} over {len(ratio)} glstat "
               f"values; car5 asks for no glstat: a wrapper deck including it adds one)", dev < 0.02 and len(ratio) >= 10)
        # the post stops the car: the post's x-force on the car (rwforc, as
        # LS-DYNA writes it: a script's max(x_force) reads the impact peak)
        # points against the car's motion, +x
        record(f"public {deck}: the post is struck (largest x-force of the post on the car {fx.max():.3e} N)",
               fx.max() > 1e3)
        record(f"public {deck}: the car slows down (mean x velocity of its history nodes {px[0]:.4e} -> "
               f"{px[-1]:.4e})", px[0] < 0 and px[-1] > 0.95 * px[0])
        # the penetration checker on the states, nodes and segments of the
        # deck's contact parts, overlaps beyond those the deck starts with:
        # no pass-through, and no overlap growing to a whole thickness (a
        # node through a shell); penalty contact leaves partial overlaps
        import penetration
        parts = [1, 2] if deck.startswith("car5") else [1, 2, 3, 4, 5]
        worst, crossings, nst, _ = penetration.check_run(out, parts, growth=True)
        record(f"public {deck}: no node through a shell of the contact parts ({nst} states: overlap growth "
               f"{worst:.3f} of the thickness, pass-throughs {crossings})", worst < 1.0 and crossings == 0)
    # the real decks on ranks (issue 32): car5 and car6 to 10 ms on 2 ranks
    # give the serial runs' motion bit for bit and their energies to
    # rounding (ranks_match: rigid bodies, walls, contact, nodout of a deck
    # written by others, not only our own test decks)
    if shutil.which("mpirun") is not None:
        for deck in ("car5_main.k", "car6_main.k"):
            ref = os.path.join(TMP, "public_" + deck[:-2])
            out = ref + "_np2"
            shutil.rmtree(out, ignore_errors=True)
            q = mpirun(2, ["i=" + os.path.join(PUBLIC, deck), "outdir=" + out, "endtim=0.010"])
            ok, msg = ranks_match(ref, out) if q.returncode == 0 else (False, q.stderr[-300:])
            record(f"public {deck} on 2 MPI ranks to 10 ms: the serial run's motion (bitwise) and energies "
                   f"(to 1e-12) {msg}", ok, q.stderr[-300:])
    # car6 with its *HOURGLASS cards' IHQ 4 set to 1 (issue 31): the shells
    # take the viscous form (d3hsp names it), whose hourglass work only
    # grows (it dissipates; 1e-9 of the energy for round-off), and the run
    # differs from the deck's own stiffness form
    src = open(os.path.join(PUBLIC, "car6_crash_v223.k")).read()
    ihq1 = re.sub(r"(?m)^(\s+\d+)(\s+)4(\s+0\.02)", r"\g<1>\g<2>1\g<3>", src)
    os.makedirs(os.path.join(TMP, "car6_ihq1"), exist_ok=True)
    with open(os.path.join(TMP, "car6_ihq1", "car6_crash_v223.k"), "w") as fh:
        fh.write(ihq1)
    shutil.copy(os.path.join(PUBLIC, "car6_main.k"), os.path.join(TMP, "car6_ihq1", "car6_main.k"))
    out1 = os.path.join(TMP, "car6_ihq1", "out")
    p = run([XDYNA, "i=" + os.path.join(TMP, "car6_ihq1", "car6_main.k"), "outdir=" + out1, "endtim=0.010"])
    log = open(os.path.join(out1, "d3hsp")).read() if p.returncode == 0 else ""
    record("public car6 with IHQ 1: runs, every shell part viscous in d3hsp",
           p.returncode == 0 and log.count("shell hourglass: viscous (IHQ 1)") == 7 and "(IHQ 4)" not in log,
           p.stderr[-300:])
    if p.returncode == 0:
        with h5py.File(os.path.join(out1, "thist.h5"), "r") as f1, \
                h5py.File(os.path.join(TMP, "public_car6_main", "thist.h5"), "r") as f4:
            hg1, tot = f1["glstat/hourglass_energy"][:], f1["glstat/total_energy"][0]
            hg4 = f4["glstat/hourglass_energy"][:]
            d1, d4 = f1["nodout/x_displacement"][-1], f4["nodout/x_displacement"][-1]
        drop = float(np.min(np.diff(hg1))) / tot
        record(f"public car6 IHQ 1: hourglass work never falls (smallest step {drop:.1e} of the energy, above -1e-9); "
               f"IHQ 4's hourglass energy at 10 ms {hg4[-1]:.3e}, IHQ 1's {hg1[-1]:.3e}, node displacements "
               f"{np.max(abs(d1 - d4)):.2e} apart", drop > -1e-9 and abs(hg1[-1] / hg4[-1] - 1) > 0.01
               and np.max(abs(d1 - d4)) > 0)
    out = os.path.join(TMP, "public_ball_plate")
    shutil.rmtree(out, ignore_errors=True)
    p = run([XDYNA, "i=" + os.path.join(PUBLIC, "ball_plate.k"), "outdir=" + out])
    record("public ball_plate.k: runs unchanged to normal termination", p.returncode == 0
           and "normal termination" in p.stdout, p.stderr[-300:])
    if p.returncode == 0:
        dev = float(np.max(abs(glstat(out)["energy_ratio"] - 1)))
        record(f"public ball_plate.k: energy ratio within 2% of 1 (largest deviation {dev:.4f})", dev < 0.02)


def test_coordinate_systems():
    """*DEFINE_COORDINATE_SYSTEM and _NODES where a CID is taken: the bar on
    the wall (input_decks/verify/bar_wall.k, -10 m/s along x) given its
    velocity as +10 m/s along the local y axis of a system whose y axis is
    global -x (O at 0, L on global y, P on global -x), by *INITIAL_VELOCITY
    ICID, and the same system from three nodes: the time histories must be
    bitwise the run's own (the axes are exact 0 and 1 here)."""
    base = open(os.path.join(ROOT, "input_decks/verify/bar_wall.k")).read()
    old = "*INITIAL_VELOCITY\n         0\n       -10         0         0\n"
    assert old in base
    p, ref = run_deck("input_decks/verify/bar_wall.k", "coord_ref")
    for label, defn in (("_SYSTEM", "*DEFINE_COORDINATE_SYSTEM\n         3       0.0       0.0       0.0       0.0"
                         "       1.0       0.0\n      -1.0       0.0       0.0\n"),
                        ("_NODES", "*NODE\n  900001             0.0             0.0             0.0\n"
                         "  900002             0.0             1.0             0.0\n"
                         "  900003            -1.0             0.0             0.0\n"
                         "*DEFINE_COORDINATE_NODES\n         3    900001    900002    900003\n")):
        deck = os.path.join(TMP, "coord.k")
        with open(deck, "w") as fh:
            fh.write(base.replace(old, defn + "*INITIAL_VELOCITY\n         0         0         0         0         3\n"
                                  "         0        10         0\n"))
        q, out = run_deck(deck, "coord" + label)
        ok = q.returncode == 0 and p.returncode == 0
        if ok:
            a, b = glstat(ref), glstat(out)
            ok = all(np.array_equal(a[k], b[k]) for k in ("kinetic_energy", "x_velocity", "total_energy"))
        record(f"coordinate systems: *INITIAL_VELOCITY ICID in *DEFINE_COORDINATE{label} gives the bar's own run "
               f"bitwise", ok, q.stderr[-300:])


def test_wall_semantics():
    """Rigid walls read as LS-DYNA documents them, each on a deck whose
    answer is known:
    - *RIGIDWALL_GEOMETRIC_CYLINDER with LENCYL 0 is infinite both ways: the
      pole deck with the tail moved 1 m above the bar (the bar lies below
      it) still stops the bar (it bounces off, y velocity > 0); with
      LENCYL 0.1 the same finite cylinder misses it (the bar keeps its
      -20 m/s within 1e-6);
    - OFFSET selects nodes, it does not move the wall: the bar 1 um from the
      wall, OFFSET 0.1 um: no node is within it, the bar passes the wall
      plane; OFFSET 10 um: the end face is held, no node ends behind x = 0;
    - a wall moved 2 mm into the bar (x = 2 mm): the end face's nodes lie
      behind it at t = 0 and are not held (each named in d3hsp); the next
      layer, 3 mm in front, is stopped on the wall (ends at x >= 2 mm less
      1e-9 of the bar's length)."""
    pole = open(os.path.join(ROOT, "input_decks/verify/bar_on_pole.k")).read()
    old = "         0        -0     -0.05         0         0      0.05         0\n      0.01       0.1         0\n"
    assert old in pole
    for label, card, hit in (("LENCYL 0 (infinite), tail 1 m above", "         0        -0       1.0         0         0       1.1         0\n      0.01       0.0         0\n", True),
                             ("LENCYL 0.1, tail 1 m above", "         0        -0       1.0         0         0       1.1         0\n      0.01       0.1         0\n", False)):
        deck = os.path.join(TMP, "pole_var.k")
        with open(deck, "w") as fh:
            fh.write(pole.replace(old, card))
        p, out = run_deck(deck, "pole_var")
        if p.returncode != 0:
            record(f"cylinder {label}: runs", False, p.stderr[-300:])
            continue
        vy = glstat(out)["y_velocity"][-1]
        if hit:
            record(f"cylinder {label}: the bar below the tail is stopped and bounces (final vy {vy:+.3f} m/s)", vy > 0)
        else:
            record(f"cylinder {label}: the finite cylinder misses the bar (final vy {vy:+.6f} m/s)",
                   abs(vy + 20) < 20e-6)
    wall = open(os.path.join(ROOT, "input_decks/verify/bar_wall.k")).read()
    old_w = "*RIGIDWALL_PLANAR_ID\n         7wall at x = 0\n         0\n         0         0         0         1         0         0\n"
    assert old_w in wall
    cases = (("OFFSET 0.1 um", "         0         0         0     1e-07\n         0         0         0         1         0         0\n", "pass"),
             ("OFFSET 10 um", "         0         0         0     1e-05\n         0         0         0         1         0         0\n", "held"),
             ("wall 2 mm into the bar", "         0\n     0.002         0         0     0.003         0         0\n", "behind"))
    for label, card, want in cases:
        deck = os.path.join(TMP, "wall_var.k")
        with open(deck, "w") as fh:
            fh.write(wall.replace(old_w, "*RIGIDWALL_PLANAR_ID\n         7wall\n" + card).replace(
                "*KEYWORD\n", "*KEYWORD\n*SET_NODE_GENERAL\n        99\nALL\n*DATABASE_HISTORY_NODE_SET\n        99\n"
                "*DATABASE_NODOUT\n   1.0e-06\n", 1))
        p, out = run_deck(deck, "wall_var")
        if p.returncode != 0:
            record(f"planar wall {label}: runs", False, p.stderr[-300:])
            continue
        with h5py.File(os.path.join(out, "thist.h5"), "r") as f:
            x = f["nodout/x_coordinate"][:]
        x0 = x[0]
        log = open(os.path.join(out, "d3hsp")).read()
        if want == "pass":
            record(f"planar wall {label}: no node selected, the bar passes the wall plane (min x {x.min():.3e} m)",
                   x.min() < 0)
        elif want == "held":
            record(f"planar wall {label}: the end face is held (min x {x.min():.3e} m >= 0)", x.min() >= -1e-12)
        else:
            face = x0 < 0.002
            named = len(re.findall(r"rigid wall 7: node \d+ lies .* behind the wall at t = 0", log))
            nxt = (x0 > 0.004) & (x0 < 0.006)
            record(f"planar wall {label}: the {int(face.sum())} end-face history nodes behind it are named "
                   f"({named} named) and the next layer is stopped on it (min x {x[:, nxt].min():.6e} m)",
                   named >= int(face.sum()) > 0 and x[:, nxt].min() >= 0.002 - 1e-9 * 0.5)


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


def test_hardening_two():
    """Issue 30's findings mended here, each on the input that showed it,
    each failing before: ncpu=100000 (a crash with no message: now exit 1
    naming the limit, finding 4); a *SET_NODE_LIST_GENERATE range of two
    billion ids and one ending at 2147483647 (gigabytes, then a failure with
    no place named; a counter that wrapped: now exit 1 naming the card,
    finding 5); r= a FIFO (hung: now exit 1, finding 6); a FIFO named
    glstat in the output directory, and o= a FIFO (hung, deaf to SIGTERM:
    now exit 1 naming it, finding 7); d3hsp's thread count with ncpu=1
    (said 2, finding 11); a contact that did positive work in a run with no
    initial energy (an 'Inf%' warning, a trap in the debug build: now the
    work alone, finding 12). Each case has 60 s to answer."""
    base = os.path.join(TMP, "hard2")
    shutil.rmtree(base, ignore_errors=True)
    os.makedirs(base)
    deck = os.path.join(ROOT, "input_decks/verify/bar_wall.k")
    text = open(deck).read()

    def answer(args, cwd=None):
        try:
            q = subprocess.run([XDYNA, *args], capture_output=True, text=True, timeout=60, cwd=cwd)
            return q.returncode, q.stderr + q.stdout
        except subprocess.TimeoutExpired:
            return None, "no answer within 60 s"

    rc, msg = answer(["i=" + deck, "outdir=" + os.path.join(base, "many"), "ncpu=100000", "endtim=1e-6"])
    record("hardening: ncpu=100000 exits 1 naming the limit", rc == 1 and "ncpu=100000" in msg
           and "processors" in msg, msg[-300:])
    for name, card in (("gen2e9", "         1 2000000000\n"), ("genwrap", " 2147483646 2147483647\n")):
        path = os.path.join(base, name + ".k")
        with open(path, "w") as fh:
            fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n*SET_NODE_LIST_GENERATE\n        77\n" + card, 1))
        rc, msg = answer(["i=" + path, "outdir=" + os.path.join(base, name + "_out")])
        if name == "gen2e9":
            good = rc == 1 and name + ".k:" in msg and "more than 50000000 ids" in msg
        else:
            # two ids: read, then refused as undefined nodes (the set is checked against the mesh)
            good = rc == 1 and name + ".k" in msg and "2147483646" in msg
        record(f"hardening: *SET_NODE_LIST_GENERATE {card.split()[0]} to {card.split()[1]} exits 1 naming the "
               f"card at once", good, msg[-300:])
    fifo = os.path.join(base, "dump_fifo")
    os.mkfifo(fifo)
    rc, msg = answer(["r=" + fifo])
    record("hardening: r= a FIFO exits 1 (not a regular file)", rc == 1 and "not a regular file" in msg, msg[-300:])
    out = os.path.join(base, "fifo_out")
    os.makedirs(out)
    os.mkfifo(os.path.join(out, "glstat"))
    rc, msg = answer(["i=" + deck, "outdir=" + out, "endtim=1e-6"])
    record("hardening: a FIFO named glstat in the output directory: exit 1 naming it", rc == 1
           and "glstat exists and is not a regular file" in msg, msg[-300:])
    os.mkfifo(os.path.join(base, "log_fifo"))
    rc, msg = answer(["i=" + deck, "outdir=" + os.path.join(base, "o_fifo"), "o=" + os.path.join(base, "log_fifo"),
                      "endtim=1e-6"])
    record("hardening: o= a FIFO: exit 1 naming it", rc == 1 and "log_fifo exists and is not a regular file" in msg,
           msg[-300:])
    out = os.path.join(base, "one_thread")
    rc, msg = answer(["i=" + deck, "outdir=" + out, "ncpu=1", "endtim=1e-6"])
    log = open(os.path.join(out, "d3hsp")).read() if rc == 0 else ""
    record("hardening: d3hsp says 'threads per rank 1' with ncpu=1", rc == 0 and "threads per rank 1" in log,
           msg[-300:])
    # a dump written from one directory with relative paths restarts from
    # another (finding 14: it made ./runs/... there and exited 2); a flipped
    # byte in the dump's stored output directory, or anywhere else in it,
    # is refused before anything is read or created (findings 2 and 3)
    work = os.path.join(base, "work")
    os.makedirs(work)
    dk = os.path.join(work, "dumped.k")
    with open(dk, "w") as fh:
        fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n*DATABASE_BINARY_D3DUMP\n         0\n", 1))
    rc, msg = answer(["i=dumped.k", "outdir=runs/a", "endtim=2e-5"], cwd=work)
    dump = os.path.join(work, "runs", "a", "d3dump.h5")
    elsewhere = os.path.join(base, "elsewhere")
    os.makedirs(elsewhere)
    rc2, msg2 = answer(["r=" + dump, "endtim=4e-5"], cwd=elsewhere)
    record("hardening: a dump written with relative paths restarts from another directory, writing where the "
           "run wrote", rc == 0 and rc2 == 0 and not os.path.exists(os.path.join(elsewhere, "runs"))
           and "N o r m a l" in open(os.path.join(work, "runs", "a", "d3hsp")).read().split("R e s t a r t")[-1],
           msg2[-300:])
    if os.path.exists(dump):
        data = bytearray(open(dump, "rb").read())
        k = data.find(os.path.join(work, "runs", "a").encode())
        flips = {"the output directory's name": k + len(work) + 3, "the middle": len(data) // 2, "the first byte": 0,
                 "the checksum": len(data) - 1}
        for what, at in flips.items():
            bad = bytearray(data)
            bad[at] ^= 0x04
            path = os.path.join(base, "flip.h5")
            open(path, "wb").write(bad)
            rc, msg = answer(["r=" + path], cwd=elsewhere)
            record(f"hardening: a dump with a flipped byte in {what} is refused (exit 1, 'checksum'), nothing "
                   f"created", k > 0 and rc == 1 and "checksum" in msg and os.listdir(elsewhere) == [], msg[-300:])
    # a deck's escape sequence echoed in an error is written escaped (finding
    # 16: the raw bytes drove the terminal)
    path = os.path.join(base, "escape.k")
    with open(path, "w") as fh:
        fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n*CONTROL_TERMINATION\n\x1b[31mred\n", 1))
    rc, msg = answer(["--check", "i=" + path])
    record("hardening: an escape sequence in a deck is echoed as \\x1B, never raw", rc == 1 and "\\x1B" in msg
           and "\x1b" not in msg, repr(msg[-300:]))
    # a serial run under a 2 MB file-size limit (finding 13: Open MPI's
    # start-up wrote a shared-memory file past it and the run died with a
    # PMIx error before a word of ours; alone, xdyna now asks PMIx for its
    # in-memory store)

    def small_files():
        resource.setrlimit(resource.RLIMIT_FSIZE, (2 * 1024 * 1024, 2 * 1024 * 1024))
    q = subprocess.run([XDYNA, "i=" + deck, "outdir=" + os.path.join(base, "ulimit"), "endtim=1e-5"],
                       capture_output=True, text=True, timeout=60, preexec_fn=small_files)
    record("hardening: a serial run under ulimit -f 2 MB starts and ends normally", q.returncode == 0
           and "normal termination" in q.stdout, (q.stdout + q.stderr)[-300:])
    dbg = XDYNA + "_debug"
    # inputs the release build refuses cleanly, refused by the debug build
    # too, not trapped (finding 17): an expression that overflows, a
    # coordinate of 1e300, a velocity of 1e300 (that one ran into the
    # energies' arithmetic: now refused at set-up, naming the node)
    lines = text.split("\n")
    j = next(i for i, l in enumerate(lines) if l.startswith("*NODE")) + 1
    while lines[j].startswith("$"):
        j += 1
    lines[j] = lines[j][:8] + "%16s" % "1.0e300" + lines[j][24:]
    odd = {"overflow": (text.replace("*KEYWORD\n", "*KEYWORD\n*PARAMETER_EXPRESSION\nR big     1.0e300*1.0e300\n", 1),
                        "not finite"),
           "coordinate": ("\n".join(lines), "inverted (volume -6.2500E+294)"),
           "velocity": (text.replace("*INITIAL_VELOCITY\n         0\n       -10", "*INITIAL_VELOCITY\n         0\n"
                                     "     1e300", 1), "beyond what the energies can hold")}
    for name, (body, expect) in odd.items():
        path = os.path.join(base, f"odd_{name}.k")
        with open(path, "w") as fh:
            fh.write(body)
        for exe in [XDYNA] + ([dbg] if os.path.exists(dbg) else []):
            q = run([exe, "i=" + path, "outdir=" + os.path.join(base, f"odd_{name}_out")])
            record(f"hardening: {name} 1e300 exits 1 in the {'debug' if exe == dbg else 'release'} build "
                   f"('{expect}')", q.returncode == 1 and expect in q.stderr, q.stderr[-300:])
    if os.path.exists(dbg):
        # the debug build restarts from a dump (finding 15: 'why' not
        # allocated) and reports a contact's work in a run with no initial
        # energy without a trap (finding 12)
        path = os.path.join(base, "dumped.k")
        with open(path, "w") as fh:
            fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n*DATABASE_BINARY_D3DUMP\n         0\n", 1))
        out = os.path.join(base, "dbg_dump")
        q = run([dbg, "i=" + path, "outdir=" + out, "endtim=2e-5"])
        q2 = run([dbg, "r=" + os.path.join(out, "d3dump.h5"), "endtim=4e-5"])
        record("hardening: the debug build restarts from its dump", q.returncode == 0 and q2.returncode == 0,
               q2.stderr[-300:])
        out = os.path.join(base, "dbg_lag")
        q = run([dbg, "i=" + os.path.join(ROOT, "input_decks/contact/block_on_block_lagrange.k"), "outdir=" + out,
                 "endcyc=2000"])
        log = open(os.path.join(out, "d3hsp")).read() if os.path.exists(os.path.join(out, "d3hsp")) else ""
        record("hardening: the Lagrangian block on block (no initial energy) ends in the debug build with no "
               "'Inf' in its contact report", q.returncode == 0 and "Inf" not in log and "NaN" not in log,
               q.stderr[-300:])
    else:
        print("SKIP hardening: the debug build is not there (make debug)")


def test_hardening():
    """Issue 18's findings that are mended, each on the input that showed it:
    - no deck or argument text reaches a shell: outdir='x$(touch F)' makes a
      directory of that very name and no file F (finding 3);
    - a *SET_NODE_LIST_GENERATE range of 3,000,000 ids gives an input error,
      not a crash (a stack temporary as large as the set; finding 5);
    - *INCLUDE of a FIFO or of /dev/zero is refused at once as not a regular
      file (it blocked for ever, or read as empty; finding 6);
    - RO = 1e999 is 'out of range' in the debug build too (the conversion
      trapped), and RO = 1e-320 is refused (a subnormal density ran with a
      'massless nodes' warning; findings 7 and 10), and a pressure on nodes
      that belong to no element stops with the node named (finding 10)."""
    base = os.path.join(TMP, "hard")
    shutil.rmtree(base, ignore_errors=True)
    os.makedirs(base)
    deck = os.path.join(ROOT, "input_decks/verify/bar_wall.k")
    odd = os.path.join(base, "x$(touch F)")
    p = run([XDYNA, "i=" + deck, "outdir=" + odd, "endtim=1e-6"], cwd=base)
    record("hardening: outdir with $(...) makes that directory and runs no shell", p.returncode == 0
           and os.path.isdir(odd) and not os.path.exists(os.path.join(base, "F")), p.stderr[-300:])
    text = open(deck).read()
    cases = [("*SET_NODE_LIST_GENERATE\n        77\n         1   3000000\n", "bigset", 1, ["bigset.k", "*SET_NODE_LIST 77"]),
             ("*INCLUDE\n/dev/zero\n", "devzero", 1, ["devzero.k", "not a regular file"]),
             ("*INCLUDE\n" + os.path.join(base, "fifo") + "\n", "fifo", 1, ["fifo.k", "not a regular file"])]
    os.mkfifo(os.path.join(base, "fifo"))
    for add, name, code, expect in cases:
        path = os.path.join(base, name + ".k")
        with open(path, "w") as fh:
            fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n" + add, 1))
        try:
            q = subprocess.run([XDYNA, "i=" + path, "outdir=" + os.path.join(base, name + "_out")], capture_output=True,
                               text=True, timeout=60)
            ok = q.returncode == code and all(e in q.stderr for e in expect)
            detail = q.stderr[-300:]
        except subprocess.TimeoutExpired:
            ok, detail = False, "no answer within 60 s"
        record(f"hardening: {name} exits {code} naming " + ", ".join(expect), ok, detail)
    # a pressure on nodes that belong to no element (finding 10): exit 1
    # naming the node, not a silent run
    col = open(os.path.join(ROOT, "input_decks/verify/pressure_column.k")).read()
    add = ("*NODE\n  900001             5.0             0.0             0.0\n  900002             6.0             0.0             0.0\n"
           "  900003             6.0             1.0             0.0\n*LOAD_SEGMENT\n        40       1.0       0.0"
           "    900001    900002    900003    900003\n")
    path = os.path.join(base, "massless_pressure.k")
    with open(path, "w") as fh:
        fh.write(col.replace("*KEYWORD\n", "*KEYWORD\n" + add, 1))
    q = run([XDYNA, "i=" + path, "outdir=" + os.path.join(base, "mp")])
    record("hardening: a pressure on nodes without mass exits 1 naming the node", q.returncode == 1
           and "node 900001" in q.stderr and "no mass" in q.stderr, q.stderr[-300:])
    # a truncated dump: one line naming it, exit 1, no HDF5 diagnostics
    # (finding 8: "written by another build (, format 0)" after 50 lines)
    path = os.path.join(base, "dumped.k")
    with open(path, "w") as fh:
        fh.write(text.replace("*KEYWORD\n", "*KEYWORD\n*DATABASE_BINARY_D3DUMP\n         0\n", 1))
    out = os.path.join(base, "dumped")
    q = run([XDYNA, "i=" + path, "outdir=" + out, "endtim=2e-5"])
    dump = os.path.join(out, "d3dump.h5")
    if q.returncode == 0 and os.path.exists(dump):
        half = os.path.join(out, "half.h5")
        shutil.copy(dump, half)
        os.truncate(half, os.path.getsize(dump) // 2)
        q = run([XDYNA, "r=" + half])
        lines = [l for l in q.stderr.splitlines() if l.strip()]
        record(f"hardening: a truncated dump exits 1 in one line naming it ({len(lines)} line(s))",
               q.returncode == 1 and len(lines) == 1 and half in lines[0] and "HDF5-DIAG" not in q.stderr,
               q.stderr[-300:])
    else:
        record("hardening: the run that writes a dump", False, q.stderr[-300:])
    # a changed byte inside a dump's array (finding 8: accepted, no
    # checksum): every dataset carries HDF5's Fletcher-32 checksum, so the
    # restart refuses it in one line naming the array
    if os.path.exists(dump):
        import h5py
        with h5py.File(dump, "r") as f:
            off = f["state/x"].id.get_chunk_info(0).byte_offset
            nbytes = f["state/x"].id.get_chunk_info(0).size
        bad = os.path.join(out, "flipped.h5")
        shutil.copy(dump, bad)
        with open(bad, "r+b") as fh:
            fh.seek(off + nbytes // 2)
            b = fh.read(1)
            fh.seek(off + nbytes // 2)
            fh.write(bytes([b[0] ^ 1]))
        q = run([XDYNA, "r=" + bad])
        lines = [l for l in q.stderr.splitlines() if l.strip()]
        record(f"hardening: one flipped bit in a dump's coordinates exits 1 naming the checksum ({len(lines)} line(s))",
               q.returncode == 1 and len(lines) == 1 and "checksum" in q.stderr and bad in q.stderr, q.stderr[-300:])
        q = run([XDYNA, "r=" + dump, "endtim=3e-5"])
        record("hardening: the undamaged dump restarts (the checksum passes)", q.returncode == 0, q.stderr[-300:])
    # SIGTERM before the parallel start-up (finding 8: exit 143, the
    # handlers came late): the run holds at its first instruction after
    # installing them (XDYNA_HOLD_AT=start), the signal comes, and it stops
    # with exit 3, no dump, since there is no state yet
    import signal
    e = dict(os.environ, XDYNA_HOLD_AT="start")
    out = os.path.join(base, "early")
    proc = subprocess.Popen([XDYNA, "i=" + deck, "outdir=" + out], cwd=base, env=e, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    proc.send_signal(signal.SIGTERM)
    so, se = proc.communicate(timeout=60)
    record("hardening: SIGTERM before the parallel start-up exits 3 cleanly, no dump",
           "held at start" in line and proc.returncode == 3 and "no restart dump" in se
           and not os.path.exists(os.path.join(out, "d3dump.h5")), f"rc={proc.returncode} {se[-300:]}")
    ro = "         1      7850 2.000e+11         0"
    assert ro in text
    for value, exe in (("1e999", XDYNA + "_debug"), ("1e999", XDYNA), ("1e-320", XDYNA)):
        path = os.path.join(base, "ro.k")
        with open(path, "w") as fh:
            fh.write(text.replace(ro, f"         1{value:>10s} 2.000e+11         0"))
        if not os.path.exists(exe):
            record(f"hardening: {os.path.basename(exe)} is built", False)
            continue
        q = run([exe, "i=" + path, "outdir=" + os.path.join(base, "ro")])
        record(f"hardening: RO = {value} is refused as out of range by {os.path.basename(exe)} (exit 1, no trap)",
               q.returncode == 1 and "field RO" in q.stderr and "out of range" in q.stderr, q.stderr[-300:])


def test_full_filesystem():
    """A full file system (issue 30, finding 1: after the right message the
    run died with SIGSEGV, exit 139, inside HDF5's clean-up at exit, when
    thist.h5 could not be written at cycle 0 or d3plot.h5 mid-run; a
    file-size limit, EFBIG, did not show it, a full disk, ENOSPC, did). A
    20 MB tmpfs filled to three levels under the tube crush with d3plot.h5:
    each run stops with exit 2 naming the file it could not write. Needs
    root to mount the tmpfs: SKIP otherwise."""
    mnt = os.path.join(TMP, "small_fs")
    os.makedirs(mnt, exist_ok=True)
    q = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=20m", "tmpfs", mnt], capture_output=True, text=True)
    if q.returncode != 0:
        print("SKIP full file system: cannot mount a tmpfs here (needs root)")
        return
    try:
        deck = os.path.join(ROOT, "input_decks/contact/tube_crush.k")
        # 18 MB free: d3plot.h5 fails mid-run (its states); 15 MB: nodout
        # mid-run; 12 MB: thist.h5 at cycle 0 (HDF5 lays out its chunks)
        for fill_kb in (2000, 5000, 8000):
            for f in os.listdir(mnt):
                p = os.path.join(mnt, f)
                shutil.rmtree(p) if os.path.isdir(p) else os.remove(p)
            with open(os.path.join(mnt, "fill"), "wb") as fh:
                try:
                    fh.write(bytes(1024 * fill_kb))
                except OSError:
                    pass
            p = run([XDYNA, "i=" + deck, "outdir=" + os.path.join(mnt, "o"), "h5plot=1", "endtim=1e-3"])
            named = re.search(r"cannot (write|create) (\S+)", p.stderr)
            record(f"full file system ({20000 - fill_kb} kB free): exit 2 naming the file, no crash "
                   f"(exit {p.returncode}: {named.group(0) if named else p.stderr[-120:]!r})",
                   p.returncode == 2 and named is not None, p.stderr[-300:])
    finally:
        subprocess.run(["umount", mnt], capture_output=True)


def test_write_failures():
    """Write failures (issue 18, finding 2: a full disk gave 430 HDF5 errors,
    "normal termination", SIGSEGV, ASCII files cut mid-line and a 0-byte
    dump temporary). A full disk is made without root or a small file
    system: the run holds at a cycle (XDYNA_HOLD_AT), the test lowers its
    file-size limit (prlimit, RLIMIT_FSIZE; writes past it fail with EFBIG
    as on a full disk), and lets it go on. Asserted: exit 2 naming the file;
    every ASCII file ends with a complete line; d3plot.h5, thist.h5 and the
    XDMF read back; a failed dump leaves no temporary and keeps the last
    good dump, which restarts."""
    import signal
    import xml.etree.ElementTree as ET

    def held_run(deck, out, hold, limit_of, before=None):
        shutil.rmtree(out, ignore_errors=True)
        e = dict(os.environ, XDYNA_HOLD_AT=str(hold), OMP_NUM_THREADS="1")
        proc = subprocess.Popen([XDYNA, "i=" + deck, "outdir=" + out, "endtim=1.0e-3"], cwd=ROOT, env=e,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = proc.stdout.readline()
        while line and not line.startswith(" held at cycle"):
            line = proc.stdout.readline()
        sizes = {f: os.path.getsize(os.path.join(out, f)) for f in os.listdir(out)}
        lim = limit_of(sizes)
        resource.prlimit(proc.pid, resource.RLIMIT_FSIZE, (lim, lim))
        if before:
            before()
        proc.send_signal(signal.SIGUSR2)   # go on
        so, se = proc.communicate(timeout=120)
        return proc.returncode, se, sizes

    deck = os.path.join(ROOT, "input_decks/contact/tube_crush.k")
    out = os.path.join(TMP, "wf_hist")
    # the limit 20 kB past nodout's size at cycle 1: nodout (or thist.h5,
    # which HDF5 has laid out further) fails at the next history output
    rc, se, sizes = held_run(deck, out, 1, lambda z: z["nodout"] + 20000)
    named = re.search(r"cannot write (\S+)", se)
    record("write failures: a file-size limit reached mid-run stops with exit 2 naming the file",
           rc == 2 and named is not None and os.path.basename(named.group(1)) in sizes, se[-300:])
    ends = {}
    for f in ("glstat", "matsum", "nodout", "rcforc"):
        data = open(os.path.join(out, f), "rb").read()
        ends[f] = data.endswith(b"\n")
    record(f"write failures: every ASCII file ends with a complete line ({ends})", all(ends.values()))
    try:
        with h5py.File(os.path.join(out, "d3plot.h5"), "r") as fh:
            nst = len(fh["states/time"])
        with h5py.File(os.path.join(out, "thist.h5"), "r") as fh:
            nrow = len(fh["glstat/time"])
        nx = sum(1 for g in ET.parse(os.path.join(out, "d3plot.xdmf")).getroot().iter("Grid")
                 if g.get("CollectionType") == "Spatial")
        good = nst >= 1 and nrow >= 1 and nx == nst
        detail = f"{nst} states, {nx} in the XDMF, {nrow} glstat rows"
    except (OSError, KeyError, ET.ParseError) as err:
        good, detail = False, str(err)
    record(f"write failures: d3plot.h5, thist.h5 and the XDMF read back ({detail})", good)
    # the dump: one every cycle; held at cycle 5 (cycle 4's dump is there),
    # the limit below the dump's size fails cycle 5's dump
    ddeck = with_cards("input_decks/contact/tube_crush.k", "wf_dump", "*DATABASE_BINARY_D3DUMP\n         1\n")
    out = os.path.join(TMP, "wf_dump")
    rc, se, sizes = held_run(ddeck, out, 5, lambda z: z["d3dump.h5"] // 2)
    tmp_left = [f for f in os.listdir(out) if f.endswith(".tmp")]
    record("write failures: a failed dump stops with exit 2 naming it and leaves no temporary",
           rc == 2 and "d3dump.h5" in se and not tmp_left, f"rc={rc} left={tmp_left} {se[-300:]}")
    q = run([XDYNA, "r=" + os.path.join(out, "d3dump.h5"), "endtim=1.2e-5"])
    record("write failures: the last good dump is kept and restarts", q.returncode == 0
           and os.path.getsize(os.path.join(out, "d3dump.h5")) > 0, q.stderr[-300:])
    # the output directory removed under a held run: the next state's XDMF
    # cannot be written, and the run says so (exit 2) instead of going on
    out = os.path.join(TMP, "wf_gone")
    rc, se, sizes = held_run(deck, out, 1, lambda z: resource.RLIM_INFINITY, before=lambda: shutil.rmtree(out))
    record("write failures: the output directory removed mid-run stops with exit 2 naming the file",
           rc == 2 and "cannot write " + out in se, f"rc={rc} {se[-300:]}")


def main():
    """Every test; with arguments, only the tests whose names contain one of
    them (for development: `tests/run_tests.py contact_friction`)."""
    tests = [unit_tests, test_bar_impact, test_free_block, test_prestressed, test_bar_wall, test_moving_walls, test_gravity_drop, test_plasticity, test_taylor_bar, test_rigid_bodies, test_rigid_wall_bodies, test_rigid_constraints, test_pressure, test_shells, test_shell_warped_spin, test_shell_hourglass_forms, test_shell_hourglass_plastic_bound, test_shell_step_length, test_element_mass, test_tied_contact, test_tiebreak, test_tiebreak_cohesive, test_erosion, test_solid_erosion, test_solid_erosion_contact, test_nodal_rigid_inertia, test_beams, test_spotweld, test_spotweld_plastic, test_shell_large_vibration, test_clamped_plate, test_subsystems, test_malformed, test_contact_surface_log, test_contact_search_interval, test_contact_fine_patch_classes, test_contact_bars, test_contact_bars_lagrange, test_lagrange_step, test_contact_block_on_block, test_contact_patch, test_contact_swept_onset, test_contact_friction, test_tube_crush, test_near_sets_exact, test_shell_fold, test_shell_on_solid, test_initial_penetration, test_penmax, test_thkchg, test_edge_contact, test_mass_scaling, test_blocks_impact, test_penetration_checker, test_wall_of_blocks, test_ascii_layout, test_lstc_layouts, test_thist_metadata, test_states, test_d3plot, test_restart, test_batch_signals, test_sense_switches, test_slurm_example, test_format_rules, test_runtime_error, test_thdiff, test_threads, test_mpi, test_mpi_metis, test_mpi_contact_own, test_mpi_owned, test_stability, test_contact_suite, test_cli, test_part_sizes, test_stack_limit, test_public_forms, test_public_decks, test_wall_semantics, test_coordinate_systems, test_lone_cube, test_hardening, test_hardening_two, test_full_filesystem, test_write_failures, test_fuzz]
    times = []
    for test in tests:
        if len(sys.argv) < 2 or any(a in test.__name__ for a in sys.argv[1:]):
            t0 = time.time()
            test()
            times.append((time.time() - t0, test.__name__))
    # XDYNA_TEST_TIMES=1: each test's wall time, longest first (to keep
    # make check within its budget)
    if os.environ.get("XDYNA_TEST_TIMES"):
        for dt, name in sorted(times, reverse=True):
            print(f"time {dt:7.1f} s  {name}")
    npass = sum(ok for _, ok in results)
    nfail = len(results) - npass
    shutil.rmtree(TMP, ignore_errors=True)
    print(f"{npass} passed, {nfail} failed")
    return 0 if nfail == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
