"""Acceptance D of issue 11 (short form): the coupled main demo (examples/mbdyn_gate, what
`./dembridge demo` runs) runs with the test peer playing gate.mbd, the gate opens under the
granular load, and the plots and dumps are written."""
import os
import shutil
import subprocess
import sys
import tempfile

import pytest

from dembridge import plugin_path
from test_fix_mbdyn import PEER

HERE = os.path.dirname(os.path.abspath(__file__))
DEMO = os.path.join(HERE, "..", "..", "examples", "mbdyn_gate", "run_demo.py")

pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")


def test_gate_demo_runs_and_writes_plots():
    out = tempfile.mkdtemp(prefix="gate", dir="/tmp")
    env = dict(os.environ, PATH="/usr/bin:/bin")  # no mbdyn: the test peer plays the gate
    p = subprocess.run([sys.executable, DEMO, "--plugin", plugin_path(), "--testpeer", PEER, "--steps", "2500",
                        "--np", "1", "--out", out], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=600)
    assert p.returncode == 0, p.stdout[-3000:]
    assert "the test peer plays gate.mbd" in p.stdout
    rows = [[float(v) for v in l.split()] for l in open(os.path.join(out, "gate.txt")) if not l.startswith("#")]
    print(p.stdout.splitlines()[-1])
    assert max(r[1] for r in rows) > 2.0          # the gate opened by degrees
    assert max(r[2] for r in rows) > 0.01         # under a granular moment that opens it
    for f in ("gate.png", "particles.0.dump", "gate_0.vtk"):
        assert os.path.getsize(os.path.join(out, f)) > 0, f
    shutil.rmtree(out, ignore_errors=True)
