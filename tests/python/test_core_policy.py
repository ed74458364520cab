"""The ctest entries' core policy (tests/pytest_plugin/dembridge_cores.py, `-p dembridge_cores`): under an entry
declared one core (DEMBRIDGE_CTEST_CORES=1) a test that is not marked two_cores and starts a program on two cores
(mpiexec -n 2+, OMP_NUM_THREADS or -pk omp above 1) fails and says to mark it, one that keeps more than one core
busy gets a warning saying so;
a marked test, a one-core test and any test outside such an entry stay what they are."""
import os
import subprocess
import sys

PLUGIN_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "pytest_plugin"))
sys.path.insert(0, PLUGIN_DIR)
from dembridge_cores import two_core_launch  # noqa: E402

CASES = '''
import os
import subprocess
import sys
import time

import pytest

import dembridge_cores

PY = [sys.executable, "-c", "pass"]

def test_mpiexec_unmarked():
    subprocess.run(["/opt/nowhere/mpiexec", "-n", "2", "lmp"])

def test_threads_unmarked():
    subprocess.run(PY, env=dict(os.environ, OMP_NUM_THREADS="2"), check=True)

def test_threads_caught_by_the_test():
    try:
        subprocess.run(PY, env=dict(os.environ, OMP_NUM_THREADS="2"))
    except RuntimeError:
        pass

@pytest.mark.TWO_CORES
def test_threads_marked():
    subprocess.run(PY, env=dict(os.environ, OMP_NUM_THREADS="2"), check=True)

@pytest.mark.parametrize("n", [1, pytest.param(2, marks=pytest.mark.TWO_CORES)])
def test_ranks_case(n):
    subprocess.run(PY, env=dict(os.environ, OMP_NUM_THREADS=str(n)), check=True)

def test_busy_unmarked(monkeypatch):
    start = dembridge_cores.cpu_seconds()
    monkeypatch.setattr(dembridge_cores, "cpu_seconds", lambda: start + 3.0)  # 3 s of CPU in ~0.6 s
    time.sleep(0.6)

def test_one_core():
    subprocess.run(PY, check=True)
'''.replace("TWO_CORES", "two_" + "cores")  # spelled apart: CMake looks for the mark to split a file's entries


def run(tmp_path, cores):
    (tmp_path / "test_cases.py").write_text(CASES)
    env = dict(os.environ, PYTHONPATH=PLUGIN_DIR, DEMBRIDGE_CTEST_CORES=cores, OMP_NUM_THREADS="1")
    p = subprocess.run([sys.executable, "-m", "pytest", "-q", "-rA", "-p", "no:cacheprovider", "-p", "dembridge_cores",
                        str(tmp_path / "test_cases.py")], capture_output=True, text=True, env=env, cwd=str(tmp_path),
                       timeout=120)
    return p.returncode, p.stdout + p.stderr


def outcomes(out):
    return {line.split(" ")[1].split("::")[-1]: line.split(" ")[0] for line in out.splitlines()
            if line.split(" ")[0] in ("PASSED", "FAILED", "ERROR")}


def test_unmarked_two_core_tests_fail_in_a_one_core_entry(tmp_path):
    rc, out = run(tmp_path, "1")
    assert rc == 1, out
    assert outcomes(out) == {"test_mpiexec_unmarked": "FAILED", "test_threads_unmarked": "FAILED",
                             "test_threads_caught_by_the_test": "FAILED", "test_threads_marked": "PASSED",
                             "test_ranks_case[1]": "PASSED", "test_ranks_case[2]": "PASSED",
                             "test_busy_unmarked": "PASSED", "test_one_core": "PASSED"}, out
    assert ("starts mpiexec -n 2 in a ctest entry declared one core: mark it @pytest.mark." + "two_cores") in out, out
    assert "test_threads_caught_by_the_test started OMP_NUM_THREADS=2 in a ctest entry declared one core" in out, out
    assert "test_busy_unmarked kept " in out and " cores busy (" in out, out  # a warning, not a failure


def test_outside_a_one_core_entry_nothing_changes(tmp_path):
    rc, out = run(tmp_path, "")
    got = outcomes(out)
    assert got.pop("test_mpiexec_unmarked") == "FAILED", out
    assert "No such file or directory: '/opt/nowhere/mpiexec'" in out, out  # started, not refused
    assert len(got) == 7 and set(got.values()) == {"PASSED"}, out
    assert "declared one core" not in out, out


def test_two_core_launches_are_recognised():
    assert two_core_launch(["/venv/bin/mpiexec", "-n", "2", "lmp", "-in", "in.deck"], {}) == "mpiexec -n 2"
    assert two_core_launch(["mpirun", "-np", "4", "lmp"], {}) == "mpiexec -n 4"
    assert two_core_launch(["/venv/bin/mpiexec", "-n", "1", "lmp"], {}) == ""
    assert two_core_launch(["lmp", "-sf", "omp", "-pk", "omp", "2"], {}) == "-pk omp 2"
    assert two_core_launch(["lmp", "-sf", "omp", "-pk", "omp", "1"], {"OMP_NUM_THREADS": "1"}) == ""
    assert two_core_launch("lmp -in in.deck", {"OMP_NUM_THREADS": "3"}) == "OMP_NUM_THREADS=3"
    assert two_core_launch(["lmp", "-n", "2"], {}) == ""  # -n of another program
