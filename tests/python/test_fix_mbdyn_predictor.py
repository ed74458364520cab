"""`predictor correct` (doc/fix_mbdyn.md, "Accuracy against MBDyn") is right only when MBDyn
integrates with `method: crank nicolson`. The test peer integrating with MBDyn's two-step `ms`
method (coupling/testpeer/oscillator_model.h) plays the split spring-mass: the fix must see from
MBDyn's predictions that they are not crank nicolson's, warn, and fall back to MBDyn's predicted
pose, so that the run is the default's (`predictor mbdyn`) bit for bit and second order against the
closed-form damped oscillation, where the unchecked correction was first order. With crank
nicolson the correction still applies (second order, better than the default)."""
import os
import shutil
import tempfile

import pytest

from dembridge import plugin_path
from test_fix_mbdyn import M, PEER, X0, Peer, analytic_x, read_traj, run_lammps, spring_mass_deck

pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")

T_END = 1.0


@pytest.fixture
def sockdir():
    d = tempfile.mkdtemp(prefix="mbp", dir="/tmp")
    yield d
    shutil.rmtree(d, ignore_errors=True)


def run(sockdir, dt, predictor, method):
    sock = os.path.join(sockdir, "p.sock")
    traj = os.path.join(sockdir, f"traj_{dt}_{predictor}_{method}.txt")
    k = int(round(T_END / dt))
    peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--steps", str(k), "--dt", repr(dt), "--mass", str(M),
                "--x0", f"{X0},0,0", "--v0", "0,0,0", "--method", method, traj=traj)
    rc, out, _ = run_lammps(spring_mass_deck(sock, dt, 1, k, extra=f"predictor {predictor}"), sockdir)
    prc, pout = peer.finish()
    assert rc == 0 and prc == 0, out[-2000:] + pout
    rows = read_traj(traj)
    return rows, max(abs(r[1] - analytic_x(r[0])) for r in rows), out


def test_predictor_correct_falls_back_to_mbdyns_pose_with_method_ms(sockdir):
    errors = {}
    for dt in (0.004, 0.002):
        ref, e_default, _ = run(sockdir, dt, "mbdyn", "ms")
        rows, e_correct, out = run(sockdir, dt, "correct", "ms")
        assert "do not follow crank nicolson's predictor" in out, out[-2000:]
        assert rows == ref  # the default's run, bit for bit
        errors[dt] = e_default
    print(f"ms: max |x - analytic| {errors[0.004]:.3e} (4 ms), {errors[0.002]:.3e} (2 ms), "
          f"ratio {errors[0.004] / errors[0.002]:.2f}")
    assert errors[0.004] / errors[0.002] > 3.5  # second order


def test_predictor_correct_still_corrects_crank_nicolson(sockdir):
    _, e_default, _ = run(sockdir, 0.004, "mbdyn", "cn")
    _, e_correct, out = run(sockdir, 0.004, "correct", "cn")
    assert "crank nicolson" not in out
    print(f"cn, 4 ms: max |x - analytic| default {e_default:.3e}, predictor correct {e_correct:.3e}")
    assert e_correct < 0.2 * e_default
