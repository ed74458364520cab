"""Acceptance D of issue 11 (short form): the coupled main demo (examples/mbdyn_gate, what
`./dembridge demo` runs) runs with the test peer playing gate.mbd, the gate opens under the
granular load, and the plots and dumps are written."""
import os
import shutil
import socket
import stat
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
    for f in ("gate.png", "snapshot.png", "particles.0.dump", "gate_0.vtk"):
        assert os.path.getsize(os.path.join(out, f)) > 0, f
    shutil.rmtree(out, ignore_errors=True)


STANDIN = r'''#!{python}
"""A stand-in for MBDyn 1.7.3 where run_demo.py relies on it: `mbdyn -f FILE -o PREFIX` changes into
FILE's folder, resolves the socket path of `socket, create, yes, path, "..."` against it, refuses a
path that already exists (`bind() failed (98: Address already in use)`, status 1), runs for the
input's final time / time step, then speaks the protocol through the test peer (gate.mbd's model)
and exits with its status (0 done, 2 interrupted by the peer)."""
import os, re, subprocess, sys
sys.path.insert(0, {demo_dir!r})
import run_demo
argv = sys.argv[1:]
f = os.path.abspath(argv[argv.index("-f") + 1])
os.chdir(os.path.dirname(f))
text = open(os.path.basename(f)).read()
path = re.search(r'socket,\s*create,\s*yes,\s*path,\s*"([^"]+)"', text).group(1)
final = eval(re.search(r"final time:\s*([^;]+);", text).group(1), {{}})
dt = float(re.search(r"time step:\s*([^;]+);", text).group(1))
sock = os.path.abspath(path)
with open({log!r}, "a") as log:
    log.write(f"cwd {{os.getcwd()}}\nsocket {{sock}}\n")
if os.path.lexists(sock):
    print(f"UseLocalSocket({{sock}}): bind() failed (98: Address already in use)", file=sys.stderr)
    sys.exit(1)
rc = subprocess.call(run_demo.testpeer_command({peer!r}, sock, round(final / dt), os.getcwd()))
with open({log!r}, "a") as log:
    log.write(f"exit {{rc}}\n")
sys.exit(rc)
'''


def test_gate_demo_runs_with_an_mbdyn_on_path():
    """`./dembridge demo` with an `mbdyn` on PATH (here the stand-in above, which places its
    socket the way the real one does) and a killed run's socket left in the output folder: the run
    reaches its end, MBDyn's socket is the one LAMMPS waits on, MBDyn ends normally with LAMMPS
    (status 0), and nothing is written beside gate.mbd."""
    work = tempfile.mkdtemp(prefix="gatem", dir="/tmp")
    out, bindir, log = os.path.join(work, "out"), os.path.join(work, "bin"), os.path.join(work, "standin.log")
    os.makedirs(bindir)
    demo_dir = os.path.dirname(os.path.abspath(DEMO))
    before = sorted(os.listdir(demo_dir))
    standin = os.path.join(bindir, "mbdyn")
    open(standin, "w").write(STANDIN.format(python=sys.executable, demo_dir=demo_dir, log=log, peer=PEER))
    os.chmod(standin, 0o755)
    # A killed run's socket at the path: MBDyn (and the stand-in) would refuse to start on it.
    os.makedirs(out)
    stale = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    stale.bind(os.path.join(out, "mbdyn.sock"))
    stale.close()
    env = dict(os.environ, PATH=bindir + ":/usr/bin:/bin")
    steps = 500  # 0.01 s of the demo's 0.25 s: 50 MBDyn steps
    p = subprocess.run([sys.executable, DEMO, "--plugin", plugin_path(), "--steps", str(steps), "--np", "1",
                        "--out", out], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=300)
    after = sorted(os.listdir(demo_dir))
    for name in set(after) - set(before):  # a socket left by a broken run: not ours to keep
        if stat.S_ISSOCK(os.lstat(os.path.join(demo_dir, name)).st_mode):
            os.unlink(os.path.join(demo_dir, name))
    assert p.returncode == 0, p.stdout[-3000:]
    assert f"using MBDyn at {standin}" in p.stdout
    assert after == before, set(after) ^ set(before)
    lines = open(log).read().split("\n")
    assert f"cwd {out}" in lines and f"socket {os.path.join(out, 'mbdyn.sock')}" in lines and "exit 0" in lines, lines
    assert "final time: 50*0.0002;" in open(os.path.join(out, "gate.mbd")).read()
    rows = [[float(v) for v in l.split()] for l in open(os.path.join(out, "gate.txt")) if not l.startswith("#")]
    assert abs(rows[-1][0] - steps * 2e-5) < 1e-12, rows[-1]
    print(p.stdout.splitlines()[-1])
    shutil.rmtree(work, ignore_errors=True)
