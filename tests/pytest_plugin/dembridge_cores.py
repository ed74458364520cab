"""pytest plugin of the ctest entries (`-p dembridge_cores`, tests/CMakeLists.txt): which tests need two cores.

ctest runs two one-core entries side by side on a two-core machine, so a test file's entry declares how many
cores it keeps busy (tests/python/CMakeLists.txt). A test that keeps two cores busy at once (``mpiexec -n 2``
or more, OpenMP threads, LIGGGHTS or a peer computing next to LAMMPS) says so::

    @pytest.mark.two_cores                                    # one test
    @pytest.mark.parametrize("n", [1, pytest.param(2, marks=pytest.mark.two_cores)])   # one case
    pytestmark = pytest.mark.two_cores                        # the whole file

Such tests run in the file's second entry (``<entry>.two_cores``, PROCESSORS 2). Under an entry declared one
core (``DEMBRIDGE_CTEST_CORES=1``) a test that was not marked and used clearly more than one core (the CPU time
of the pytest process and of its finished children over the test's wall time, fixtures included), or that
started a program on two cores (``mpiexec -n 2`` or more, ``OMP_NUM_THREADS`` or ``-pk omp`` above 1; found
whatever the machine's load), fails and says to mark it: the scheduling stays true when tests are added.
"""
import os
import resource
import subprocess
import time

import pytest

MARK = "two_cores"
# a one-core test's CPU time can only exceed its wall time by measurement noise; two busy cores give ~2
RATIO = 1.3
MIN_WALL = 0.5  # seconds: shorter tests cannot delay a neighbour entry noticeably


def pytest_configure(config):
    if allowed_cores() == 1:
        subprocess.Popen = _WatchedPopen  # subprocess.run and check_output start their programs through it
    config.addinivalue_line("markers", f"{MARK}: keeps two cores busy at once (mpiexec -n 2+, OpenMP threads, two "
                                       "programs computing side by side); runs in the file's PROCESSORS 2 ctest entry "
                                       "(tests/pytest_plugin/dembridge_cores.py)")


def two_core_launch(args, env):
    """Why the command line args (with environment env) keeps two cores busy, or ''."""
    args = [str(a) for a in ([args] if isinstance(args, (str, bytes, os.PathLike)) else args)]
    for i, a in enumerate(args):
        nxt, after = (args[i + 1:i + 3] + ["", ""])[:2]
        if a in ("-n", "-np") and any(os.path.basename(b) in ("mpiexec", "mpirun") for b in args[:i]) \
                and nxt.isdigit() and int(nxt) > 1:
            return f"mpiexec -n {nxt}"
        if a in ("-pk", "-package") and nxt == "omp" and after.isdigit() and int(after) > 1:
            return f"-pk omp {after}"
    threads = (env if env is not None else os.environ).get("OMP_NUM_THREADS", "1")
    return f"OMP_NUM_THREADS={threads}" if threads.isdigit() and int(threads) > 1 else ""


_current = {}  # the running test's two-core launches


class _WatchedPopen(subprocess.Popen):
    def __init__(self, args, *rest, **kw):
        why = two_core_launch(args, kw.get("env"))
        item = _current.get("item")
        if why and item is not None and not item.get_closest_marker(MARK):
            _current.setdefault("launches", []).append(why)  # fails the test even if it catches the error
            self.args, self._child_created, self.returncode = args, False, None  # what __repr__ and __del__ read
            raise RuntimeError(f"{item.nodeid} starts {why} in a ctest entry declared one core: "
                               f"mark it @pytest.mark.{MARK} (tests/pytest_plugin/dembridge_cores.py)")
        super().__init__(args, *rest, **kw)


def cpu_seconds():
    """CPU time of this process and of its children that have finished (user + system)."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def allowed_cores():
    value = os.environ.get("DEMBRIDGE_CTEST_CORES", "")
    return int(value) if value.isdigit() else 0


@pytest.hookimpl(hookwrapper=True, tryfirst=True)
def pytest_runtest_protocol(item, nextitem):
    item._dembridge_cores_start = (time.monotonic(), cpu_seconds())
    _current.clear()
    _current["item"] = item
    yield
    _current.clear()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    rep = outcome.get_result()
    if call.when != "call" or not rep.passed or allowed_cores() != 1 or item.get_closest_marker(MARK):
        return
    wall0, cpu0 = item._dembridge_cores_start
    wall, cpu = time.monotonic() - wall0, cpu_seconds() - cpu0
    launches = sorted(set(_current.get("launches", [])))
    if not launches:
        if wall >= MIN_WALL and cpu > RATIO * wall:
            # a warning, not a failure: children's CPU is counted when they are reaped, so a process a fixture
            # started earlier can land on this test; only the launches above are certain
            item.warn(pytest.PytestWarning(
                f"{item.nodeid} kept {cpu / wall:.1f} cores busy ({cpu:.1f} s CPU in {wall:.1f} s) in a ctest entry "
                f"declared one core: if it computes on two cores at once, mark it @pytest.mark.{MARK}"))
        return
    why = "started " + ", ".join(launches)
    rep.outcome = "failed"
    rep.longrepr = (f"{item.nodeid} {why} in a ctest entry declared one core: mark it @pytest.mark.{MARK} so that "
                    "it runs in the file's PROCESSORS 2 entry (tests/pytest_plugin/dembridge_cores.py)")
