"""The test peer's modal body (mbdyn_testpeer --modal-*, which plays examples/flexible_blade) against
the recorded MBDyn 1.7.3 modal run and a closed form:
- what it copies from MBDyn, checked on the recorded loose modal_body run (tests/data/mbdyn-ext): the
  kinematics message of step k carries the modal coordinates and rates of MBDyn's converged step k-1
  (its .mod output), and MBDyn's modal states obey crank nicolson, q_k - q_k-1 = T/2 (q'_k-1 + q'_k),
  and the same for q' with q'';
- that it sends what MBDyn sends (t0, then at step k its state of step k - 1), bit for bit;
- its modal equation, against the closed-form free vibration of a damped mode (p = 0): second order
  in the time step. (The recorded modal runs are of a free body; a clamped one was not recorded.)"""
import csv
import gzip
import math
import os
import socket
import struct
import subprocess
import time

import pytest

from test_fix_mbdyn import PEER, sockdir  # noqa: F401 (fixture)

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "modal_body")
T = 2e-3  # the recorded run's time step


def recorded_mod():
    """{mode: [(q, q', q'') at t0, step 1, ...]} of MBDyn's loose.mod."""
    out = {1: [], 2: []}
    with gzip.open(os.path.join(DATA, "loose.mod.gz"), "rt") as f:
        for line in f:
            label, q, qd, qdd = line.split()
            out[int(label.split(".")[1])].append((float(q), float(qd), float(qdd)))
    return out


def test_recorded_mbdyn_sends_the_modal_states_of_the_last_converged_step():
    mod = recorded_mod()
    with open(os.path.join(DATA, "transcript_loose.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["dir"] == "mbdyn->peer" and r["cmd"] == "6"]
    checked = 0
    for r in rows:
        step = (int(r["seq"]) - 2) // 2  # seq 2: t0, then one message and one answer per step
        v = [float(x) for x in r["values"].split()]
        prev = max(step - 1, 0)  # t0 and step 1 both carry the initial state
        for m in (1, 2):
            assert v[17 + m] == mod[m][prev][0] and v[19 + m] == mod[m][prev][1], (step, m)
        checked += 1
    assert checked == 51


def test_recorded_modal_states_obey_crank_nicolson():
    mod = recorded_mod()
    worst = 0.0
    for m in (1, 2):
        s = mod[m]
        assert len(s) == 501
        sq = max(abs(x[0]) for x in s)
        sd = max(abs(x[1]) for x in s)
        for k in range(1, len(s)):
            worst = max(worst, abs(s[k][0] - s[k - 1][0] - T / 2 * (s[k - 1][1] + s[k][1])) / sq,
                        abs(s[k][1] - s[k - 1][1] - T / 2 * (s[k - 1][2] + s[k][2])) / sd)
    print(f"recorded modal states: crank nicolson identities to {worst:.1e} of the largest value")
    assert worst <= 1e-12


def free_mode(sock, traj, dt, steps, k, c, q0):
    """The test peer with one mode (mass 1), answered p = 0 by a client playing fix mbdyn modal."""
    peer = subprocess.Popen([PEER, "--path", sock, "--steps", str(steps), "--dt", repr(dt), "--modal-mass", "1",
                             "--modal-stiffness", repr(k), "--modal-damping", repr(c), "--modal-q0", repr(q0),
                             "--trajectory", traj, "--accept-timeout", "20", "--io-timeout", "20"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    s = socket.socket(socket.AF_UNIX)
    for _ in range(400):
        try:
            s.connect(sock)
            break
        except OSError:
            time.sleep(0.025)
    s.sendall(struct.pack("=BII", 7, 1, 1))
    assert s.recv(1) == b"\x08"
    sent = []
    while True:
        cmd = s.recv(1)
        if cmd != b"\x06":
            break
        got = b""
        while len(got) < 16:
            got += s.recv(16 - len(got))
        sent.append(struct.unpack("=dd", got))
        s.sendall(b"\x06" + struct.pack("=d", 0.0))
    s.close()
    assert peer.wait(timeout=30) == 0, peer.stdout.read()
    rows = [[float(v) for v in l.split()] for l in open(traj) if not l.startswith("#")]
    # as MBDyn: t0, then at step k the state of step k - 1 (step 1: t0's)
    assert [tuple(rows[max(j - 1, 0)][1:3]) for j in range(len(sent))] == sent
    return rows


@pytest.mark.skipif(PEER is None, reason="needs the mbdyn_testpeer executable (build it)")
def test_peer_free_mode_is_the_closed_form_to_second_order(sockdir):  # noqa: F811
    w, zeta, q0, t_end = 2 * math.pi * 10.0, 0.02, 0.01, 0.2
    wd = w * math.sqrt(1 - zeta * zeta)
    exact = lambda t: q0 * math.exp(-zeta * w * t) * (math.cos(wd * t) + zeta / math.sqrt(1 - zeta ** 2) * math.sin(wd * t))  # noqa: E731,E501
    errors = []
    for dt in (1e-3, 5e-4):
        rows = free_mode(f"{sockdir}/m.sock", f"{sockdir}/t.txt", dt, round(t_end / dt), w * w, 2 * zeta * w, q0)
        errors.append(max(abs(r[1] - exact(r[0])) for r in rows) / q0)
    print(f"free mode: max |q - q_exact| / q0 = {errors[0]:.3e} (1 ms), {errors[1]:.3e} (0.5 ms), "
          f"ratio {errors[0] / errors[1]:.2f}")
    assert errors[0] < 2e-2 and 3.8 < errors[0] / errors[1] < 4.2
