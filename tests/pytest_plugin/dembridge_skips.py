"""pytest plugin of the ctest entries (`-p dembridge_skips`, tests/CMakeLists.txt): a skipped test fails.

Under ``./dembridge test`` every prerequisite of a test is built or installed, so a skip means a test
that did not check what it claims (e.g. the MBDyn peer missing and the real-MBDyn comparisons never run).
A test that may skip on a machine for a reason that is not a defect declares it::

    @pytest.mark.expected_skip("why the skip is expected on this machine")

Its skip stays a skip (reported with that reason). An xfail is not a skip. A module skipped at
collection (``pytest.skip(allow_module_level=True)``, ``importorskip``) always fails: declare the
reason on the tests instead. Run pytest without ``-p dembridge_skips`` to get pytest's own behaviour.
"""
import pytest

MARK = "expected_skip"


def pytest_configure(config):
    config.addinivalue_line("markers", f"{MARK}(reason): this test may skip on this machine for the reason given; "
                                       "under ctest any other skip is a failure (tests/pytest_plugin/dembridge_skips.py)")


def declared_reason(item):
    m = item.get_closest_marker(MARK)
    if m is None:
        return ""
    reason = m.kwargs.get("reason", m.args[0] if m.args else "")
    return reason.strip() if isinstance(reason, str) else ""


def _skip_message(rep):
    lr = rep.longrepr
    return lr[2] if isinstance(lr, tuple) and len(lr) == 3 else str(lr)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    rep = outcome.get_result()
    if rep.skipped and not hasattr(rep, "wasxfail") and not declared_reason(item):
        rep.outcome = "failed"
        rep.longrepr = (f"{item.nodeid} was skipped ({_skip_message(rep)}), and it does not declare the skip as expected "
                        f"on this machine (@pytest.mark.{MARK}(\"why\")); under ctest a skip is a failure: build or "
                        "install what the test needs, or declare why it may be missing")


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector):
    outcome = yield
    rep = outcome.get_result()
    if rep.skipped:
        rep.outcome = "failed"
        rep.longrepr = (f"{collector.nodeid} was skipped at collection ({_skip_message(rep)}); under ctest a skip is a "
                        f"failure: declare an expected skip on the tests (@pytest.mark.{MARK}(\"why\")) instead")
