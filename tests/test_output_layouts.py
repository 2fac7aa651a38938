"""Output layouts: the ASCII histories against LS-DYNA's, thist.h5's metadata,
thdiff.

Each check states its tolerance and why (tests/README.md: how to run
and add tests)."""
import pytest

from xdtest import *  # noqa: F401,F403 (the shared helpers and imports)


@pytest.mark.xdist_group("bar_impact")
def test_thdiff(bar_impact_run):
    """(e) thdiff accepts a run against itself and rejects a perturbed one."""
    base = bar_impact_run[1]
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
        skip("ASCII layout: ../shared/reference-output is not here")
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
