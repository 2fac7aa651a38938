"""What the test modules share: where the builds are, how a deck is run,
how a check is recorded, and the helpers more than one subject uses.

A check is `record(name, ok, detail)`: under pytest (tests/conftest.py)
each is a subtest of its test function, reported and counted on its own,
and a failed one fails `make check` naming the test and the check; called
from a script (tools/verify.py) it prints PASS or FAIL and is kept in
`results`. Every check states its tolerance and why, at the check.
"""
# (the test modules take these imports too, through `from xdtest import *`)
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

# The deck tests read the states from d3plot.h5 (h5py): every run here writes
# it beside the d3plot family (xdyna's default writes the family alone;
# test_d3plot checks that default with XDYNA_H5PLOT=0)
os.environ.setdefault("XDYNA_H5PLOT", "1")

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
THDIFF = os.path.join(ROOT, "bin", "thdiff")
TMP = tempfile.mkdtemp(prefix="xdyna-tests-")
results = []


# the current test's way of reporting a check (conftest.py sets it for each
# test function; None: print it)
_reporter = None


def set_reporter(reporter):
    """reporter(name, ok, detail) for the checks that follow (None: print
    them); returns the one it replaces."""
    global _reporter
    old, _reporter = _reporter, reporter
    return old


def record(name, ok, detail=""):
    """One check: `ok` is its assertion, `name` says what it asserts, with
    its tolerance and the figure found; `detail` is shown when it fails."""
    ok = bool(ok)
    results.append((name, ok))
    if os.environ.get("XDYNA_CHECK_LOG"):
        with open(os.environ["XDYNA_CHECK_LOG"], "a") as f:
            f.write(("PASS " if ok else "FAIL ") + name + "\n")
    if _reporter is not None:
        # a failed check names the test's line that made it
        caller = sys._getframe(1)
        where = f"{os.path.relpath(caller.f_code.co_filename, ROOT)}:{caller.f_lineno}"
        _reporter(name, ok, detail if ok else f"{where}: {name}" + (f"\n{detail}" if detail else ""))
    else:
        print(("PASS " if ok else "FAIL ") + name + ("" if ok or not detail else ": " + detail), flush=True)


def skip(reason):
    """A part of a test that cannot run here (a missing reader, corpus or
    privilege): a skip with its reason, not a pass; the test goes on."""
    if _reporter is not None:
        _reporter(reason, None, "")
    else:
        print("SKIP " + reason, flush=True)


# the longest any one command of a test may take (XDYNA_TEST_TIMEOUT,
# seconds): the longest takes about a minute on two cores; a run that hangs
# (ranks waiting on each other in different collectives) fails its check
# instead of holding make check until CI's limit
TIMEOUT = float(os.environ.get("XDYNA_TEST_TIMEOUT", "600"))


def run(args, cwd=None, env=None):
    """The command's CompletedProcess; past TIMEOUT its whole process group
    (mpirun and its ranks) is killed and the result says so (exit -9)."""
    e = dict(os.environ)
    e.setdefault("OMP_NUM_THREADS", "1")
    if env:
        e.update(env)
    proc = subprocess.Popen(args, cwd=cwd or ROOT, env=e, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        # SIGTERM first: mpirun passes it to its ranks (which are not in its
        # process group) and ends them
        os.killpg(proc.pid, 15)
        try:
            out, err = proc.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, 9)
            out, err = proc.communicate()
        err += f"\n(killed: still running after {TIMEOUT:.0f} s, XDYNA_TEST_TIMEOUT)"
    return subprocess.CompletedProcess(args, proc.returncode, out, err)


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


def vtk_blocks(reader):
    """The blocks of a vtkLSDynaReader's output: (name, grid) for each part."""
    out = reader.GetOutput()
    blocks = []
    for i in range(out.GetNumberOfBlocks()):
        b = out.GetBlock(i)
        if b is not None:
            blocks.append((out.GetMetaData(i).Get(out.NAME()), b))
    return blocks


def mpi_missing():
    """True (and a failed check recorded) where mpirun is not installed: an
    MPI test then has nothing to run."""
    if shutil.which("mpirun") is None:
        record("mpirun is installed (make deps: openmpi-bin)", False)
        return True
    return False


def gen_deck(*args):
    """tools/gen_decks.py with these arguments (a generated model deck)."""
    return run([sys.executable, os.path.join(ROOT, "tools", "gen_decks.py"), *args])


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


def interface_line(log, field):
    """Numbers of the summary row of the first interface: id, slaves,
    searches, masters/slave, pool/slave, reduced/slave, seconds, ns, max 4u/delta."""
    lines = log.split("c o n t a c t   s e a r c h   s u m m a r y")[1].splitlines()
    return [float(v) for v in lines[2].split()][field]


_bar_impact = None


def bar_impact_run():
    """The elastic bar struck at one end (input_decks/verify/bar_impact.k),
    run once a process: its checks, the log's subsystem lines and thdiff's
    tests read the same run (the `bar_impact_run` fixture)."""
    global _bar_impact
    if _bar_impact is None:
        _bar_impact = run_deck("input_decks/verify/bar_impact.k", "bar_impact")
    return _bar_impact
