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
from test_fix_mbdyn import C, K, M, PEER, X0, Peer, analytic_x, read_traj, run_lammps, spring_mass_deck

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


def trapezoidal_spring_mass(dt, t_end):
    """MBDyn alone on the whole split spring-mass: m x'' = -K x - C x' by crank nicolson on the
    momentum q (q' = F, v = q / m, MBDyn's initial derivatives q0 = m v0 + 1e-6 dt F0), each step
    solved exactly; x per step. The coupled run's distance to it is the coupling's own error (the
    closed form also holds crank nicolson's, 2e-5 at 4 ms)."""
    h = 0.5 * dt
    x, v = X0, 0.0
    F = -K * x - C * v
    q = M * v + 1e-6 * dt * F
    out = [x]
    for _ in range(int(round(t_end / dt))):
        # q1 = q + h (F + F1), x1 = x + h (v + q1 / M), F1 = -K x1 - C q1 / M: linear in q1
        q1 = (q + h * F - h * K * (x + h * v)) / (1 + h * (K * h + C) / M)
        v1 = q1 / M
        x1 = x + h * (v + v1)
        q, v, x = q1, v1, x1
        F = -K * x - C * v
        out.append(x)
    return out


def run_with(sockdir, dt, extra, peer_extra):
    sock = os.path.join(sockdir, "p.sock")
    traj = os.path.join(sockdir, f"traj_{dt}_{len(extra)}.txt")
    k = int(round(T_END / dt))
    peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--steps", str(k), "--dt", repr(dt), "--mass", str(M),
                "--x0", f"{X0},0,0", "--v0", "0,0,0", *peer_extra, traj=traj)
    rc, out, _ = run_lammps(spring_mass_deck(sock, dt, 1, k, extra=extra), sockdir)
    prc, pout = peer.finish()
    assert rc == 0 and prc == 0, out[-2000:] + pout
    rows = read_traj(traj)
    alone = trapezoidal_spring_mass(dt, T_END)
    assert len(rows) == len(alone)
    return max(abs(r[1] - analytic_x(r[0])) for r in rows), max(abs(r[1] - y) for r, y in zip(rows, alone))


def test_predictor_correct_with_accelerations_is_third_order(sockdir):
    # accelerations yes: the end-of-step velocity from MBDyn's accelerations of the two steps before
    # (v* - v_{k-1} = T/2 (3 a_{k-1} - a_{k-2})) instead of v_{k-1} - v_{k-2}
    fig = {}
    for dt in (0.004, 0.002, 0.001):
        fig[dt] = (run_with(sockdir, dt, "predictor correct", ()),
                   run_with(sockdir, dt, "predictor correct accelerations yes", ("--accelerations",)))
    line = "; ".join(f"{dt * 1e3:g} ms: closed form {p[0]:.3e} -> {a[0]:.3e}, trapezoidal alone {p[1]:.3e} -> "
                     f"{a[1]:.3e}" for dt, (p, a) in fig.items())
    print("predictor correct, without -> with accelerations, max |x - x_ref|: " + line)
    (p4, a4), (p2, a2), (p1, a1) = fig[0.004], fig[0.002], fig[0.001]
    # the coupling error (against crank nicolson alone): second order without, third with
    assert p4[1] / p2[1] > 3.5 and p2[1] / p1[1] > 3.5
    assert a4[1] / a2[1] > 7.0 and a2[1] / a1[1] > 7.0
    assert all(a[1] < 0.2 * p[1] for p, a in fig.values())
    # against the closed form: never worse (the rest is crank nicolson's own error)
    assert all(a[0] <= p[0] for p, a in fig.values())
