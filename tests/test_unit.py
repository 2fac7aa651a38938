"""The Fortran unit tests (tests/unit, built by `make tests`): each binary
is a test, each case it prints (PASS or FAIL and its name) a check."""
import glob
import os

import pytest

from xdtest import ROOT, record, run

BINARIES = sorted(glob.glob(os.path.join(ROOT, "build", "tests", "test_*")))


@pytest.mark.parametrize("exe", BINARIES, ids=[os.path.basename(b)[5:] for b in BINARIES])
def test_unit(exe):
    p = run([exe])
    lines = [l for l in p.stdout.splitlines() if l.startswith(("PASS ", "FAIL "))]
    for l in lines:
        record("unit/" + os.path.basename(exe)[5:] + ": " + l[5:].split(": ")[0], l.startswith("PASS"), l[5:])
    # a crash or a binary that printed no case is a failed check of its own
    if p.returncode != 0 or not lines:
        record("unit/" + os.path.basename(exe) + " ran to the end", False, p.stderr[-400:])
