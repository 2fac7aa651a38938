#!/usr/bin/python3
"""make verify: run the verification problems (the deck tests of
tests/ with known answers) and write doc/verification.md with
each check's figure, tolerance, pass/fail and the wall time of its problem.
Exit 1 if any check fails."""
import datetime
import os
import platform
import re
import shutil
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))
import xdtest as rt  # noqa: E402 (the checks' record, the build, the runs' directory)
import test_contact_decks as cd  # noqa: E402
import test_elements as el  # noqa: E402
import test_materials as ma  # noqa: E402
import test_parallel as pa  # noqa: E402
import test_walls_bodies_loads as wb  # noqa: E402

PROBLEMS = [
    ("Elastic bar struck at one end (1-D wave)", "1-D theory: c = sqrt(E/rho), sigma = rho c v0",
     lambda: el.test_bar_impact(rt.bar_impact_run())),
    ("Free block translating and spinning", "conservation of energy and momentum", el.test_free_block),
    ("Pre-stressed column released", "conservation of energy; sigma^2 V / 2E", el.test_prestressed),
    ("Elastic bar on a planar rigid wall", "1-D theory: 2L/c, rho c A v0, rebound at v0", wb.test_bar_wall),
    ("Moving and cylindrical rigid walls", "fixed-wall limit; momentum and energy; no penetration",
     wb.test_moving_walls),
    ("Block dropped on a rigid wall under gravity", "v = sqrt(2 g h)", wb.test_gravity_drop),
    ("One element in uniaxial stress, plastic materials", "closed-form return mapping; Cowper-Symonds",
     ma.test_plasticity),
    ("Taylor bar (copper, 227 m/s)", "final length 21.45 mm, foot radius 7.2 mm (issue 3's reference)",
     ma.test_taylor_bar),
    ("Rigid bodies", "closed-form box inertia; torque-free conservation; rod with end mass",
     wb.test_rigid_bodies),
    ("Rigid body on a planar rigid wall", "plastic impact: the wall takes the kinetic energy; no node behind it",
     wb.test_rigid_wall_bodies),
    ("Prescribed rigid motion and spot welds", "the prescribed curves; conservation; failure time",
     wb.test_rigid_constraints),
    ("Column under segment pressure", "uniaxial stress: p L / E", wb.test_pressure),
    ("Belytschko-Tsay cantilever strip", "beam theory, first bending frequency", el.test_shells),
    ("Clamped square plate under pressure", "plate theory: 0.00126 q a^4 / D", el.test_clamped_plate),
    ("Two bars meeting head-on through contact", "1-D theory: 2L/c, velocities reversed; momentum",
     cd.test_contact_bars),
    ("Block resting on a block, penalty contact", "static penetration m g / k", cd.test_contact_block_on_block),
    ("Contact patch test", "a uniform pressure passes through a contact interface undisturbed",
     cd.test_contact_patch),
    ("Cube sliding and sticking on a plate", "Coulomb friction: deceleration mu g; static limit",
     cd.test_contact_friction),
    ("Square tube axial crush (shells, self-contact)", "Abramowicz & Jones mean force; no pass-through",
     cd.test_tube_crush),
    ("Thread count", "deterministic assembly: bitwise equal histories", pa.test_threads),
]


CHECK = re.compile(r"^(?P<q>.*?) (?:within|to|under|below) (?P<tol>[0-9.e+-]+ ?%?)(?: of (?P<ref>.*?))? "
                   r"\((?P<res>[^()]*)\)$")


def columns(name):
    """A check's name split into quantity, tolerance, reference and result
    where it has the form 'quantity within TOL of REF (RESULT)'; otherwise
    the whole name is the quantity."""
    m = CHECK.match(name)
    if not m:
        return name, "", "", ""
    return m.group("q"), m.group("tol").strip(), m.group("ref") or "", m.group("res")


def main():
    docname = "verification-single.md" if rt.SINGLE else "verification.md"
    build = (" with the 32-bit build (`make PRECISION=single verify`: field data in 32 bits, energies and time "
             "in 64; round-off tolerances scaled as `roundoff()` in tests/xdtest.py states)") if rt.SINGLE else ""
    lines = ["# Verification" + (" (32-bit build)" if rt.SINGLE else ""), "",
             f"Written by `make verify`{build} on {datetime.date.today().isoformat()} "
             f"({platform.machine()}, {os.cpu_count()} cores). Each check states its quantity, the "
             "reference it is held to (the problem's source in the second column), its result (the error "
             "where the check is a relative one), the tolerance and pass/fail; the reasons for the "
             "tolerances are in the tests (`tests/test_*.py`). Wall time is that of the whole problem (all its "
             "runs), one thread unless stated. Error against run time for each knob: `doc/accuracy.md` "
             "(`make sweeps`); stiff and extreme cases: below (`make stability`).", "",
             "| problem | reference (source) | quantity | against | result | tolerance | pass | wall (s) |",
             "|---|---|---|---|---|---|---|---|"]
    nfail = 0
    for title, ref, fn in PROBLEMS:
        start = len(rt.results)
        t0 = time.time()
        fn()
        wall = time.time() - t0
        rows = rt.results[start:]
        for k, (name, ok) in enumerate(rows):
            nfail += not ok
            q, tol, against, res = columns(name)
            lines.append(f"| {title if k == 0 else ''} | {ref if k == 0 else ''} | {q} | {against} | {res} | "
                         f"{tol} | {'yes' if ok else '**no**'} | {f'{wall:.1f}' if k == 0 else ''} |")
    lines += ["", f"{len(rt.results) - nfail} checks passed, {nfail} failed."]
    # the stability summary (make stability) stays below its marker
    doc = os.path.join(ROOT, "doc", docname)
    tail = ""
    if os.path.exists(doc) and "<!-- stability -->" in open(doc).read():
        tail = "\n<!-- stability -->" + open(doc).read().split("<!-- stability -->", 1)[1]
    with open(doc, "w") as f:
        f.write("\n".join(lines) + "\n" + tail)
    shutil.rmtree(rt.TMP, ignore_errors=True)
    print(f"verify: wrote doc/{docname} ({len(rt.results) - nfail} passed, {nfail} failed)")
    return 1 if nfail else 0


if __name__ == "__main__":
    sys.exit(main())
