"""The ctest entries' skip policy (tests/pytest_plugin/dembridge_skips.py, `-p dembridge_skips`): a skipped
test fails unless it declares the skip expected (@pytest.mark.expected_skip("why")); an xfail, a pass and a
declared skip stay what they are; a module skipped at collection fails."""
import os
import subprocess
import sys

PLUGIN_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "pytest_plugin"))

CASES = '''
import pytest

def test_plain_skip():
    pytest.skip("the peer is not built")

@pytest.mark.skipif(True, reason="condition true")
def test_skipif():
    pass

@pytest.mark.expected_skip("this machine has no GPU")
def test_declared():
    pytest.skip("no GPU")

@pytest.mark.expected_skip("")
def test_declared_without_reason():
    pytest.skip("no GPU")

@pytest.mark.xfail(reason="known", strict=True)
def test_xfail():
    assert False

def test_pass():
    pass
'''


def run(tmp_path, text, name="test_cases.py"):
    (tmp_path / name).write_text(text)
    env = dict(os.environ, PYTHONPATH=PLUGIN_DIR)
    p = subprocess.run([sys.executable, "-m", "pytest", "-q", "-rA", "-p", "no:cacheprovider", "-p", "dembridge_skips",
                        str(tmp_path / name)], capture_output=True, text=True, env=env, cwd=str(tmp_path), timeout=120)
    return p.returncode, p.stdout + p.stderr


def outcome(out, test):
    for line in out.splitlines():
        if line.split(" ")[0] in ("PASSED", "FAILED", "ERROR", "SKIPPED", "XFAIL") and test in line:
            return line.split(" ")[0]
    return None


def test_undeclared_skips_fail_declared_ones_stay_skips(tmp_path):
    rc, out = run(tmp_path, CASES)
    assert rc == 1, out
    assert outcome(out, "test_plain_skip") == "FAILED", out
    assert outcome(out, "test_skipif") == "ERROR", out  # skipif acts in setup: a setup failure
    assert outcome(out, "test_declared_without_reason") == "FAILED", out
    assert outcome(out, "test_declared ") is None and "SKIPPED [1]" in out and "no GPU" in out, out
    assert outcome(out, "test_xfail") == "XFAIL", out
    assert outcome(out, "test_pass") == "PASSED", out
    assert "does not declare the skip as expected on this machine" in out


def test_module_skipped_at_collection_fails(tmp_path):
    rc, out = run(tmp_path, 'import pytest\npytest.importorskip("no_such_module_here")\n\ndef test_x():\n    pass\n',
                  "test_module_skip.py")
    assert rc != 0 and "skipped at collection" in out, out
