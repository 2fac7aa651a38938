"""pytest's set-up for xdyna's suite.

- Each `record(name, ok, detail)` of a test function (xdtest.py) is a
  subtest (pytest-subtests): reported, counted and failed on its own, named
  by its check; a `skip(reason)` is a skipped subtest with its reason.
- Runs that several tests read are session fixtures (`bar_impact_run`).
- The suite ends, after pytest's own summary, with the line
  `N passed, N failed` counting checks: the subtests, plus every test
  function that failed outside its checks (an exception, a fixture) or
  has no check of its own.
"""
import shutil

import pytest

import xdtest


@pytest.fixture(autouse=True)
def _checks(subtests):
    def report(name, ok, detail):
        with subtests.test(msg=name):
            if ok is None:
                pytest.skip(name)
            assert ok, detail
    old = xdtest.set_reporter(report)
    yield
    xdtest.set_reporter(old)


@pytest.fixture(scope="session")
def bar_impact_run():
    """(process, output directory) of input_decks/verify/bar_impact.k."""
    return xdtest.bar_impact_run()


def pytest_collection_modifyitems(items):
    # the slow tests first, longest first (slow(seconds): its time on two
    # cores; a stable sort: the rest keep their order), so that the workers
    # do not wait at the end on one long test
    def seconds(item):
        mark = item.get_closest_marker("slow")
        return -(mark.args[0] if mark and mark.args else 0)
    items.sort(key=seconds)


_config = None
_tally = {"passed": 0, "failed": 0, "skipped": 0}
_checked = set()    # test functions that reported at least one check


def pytest_configure(config):
    global _config
    _config = config


def _counting():
    # the xdist workers' reports reach the controller, which counts them
    return _config is not None and not hasattr(_config, "workerinput")


def pytest_runtest_logreport(report):
    if not _counting():
        return
    if hasattr(report, "context"):          # a check (subtest)
        _checked.add(report.nodeid)
        if report.when == "call":
            _tally[report.outcome] += 1
        return
    if report.failed:
        _tally["failed"] += 1
    elif report.when == "call" and report.nodeid not in _checked:
        _tally[report.outcome] += 1
    elif report.skipped and report.when == "setup":
        _tally["skipped"] += 1


def pytest_unconfigure(config):
    shutil.rmtree(xdtest.TMP, ignore_errors=True)
    if not _counting():
        return
    if _tally["skipped"]:
        print(f"checks skipped: {_tally['skipped']} (their reasons above)")
    print(f"{_tally['passed']} passed, {_tally['failed']} failed")
