"""The test peer (mbdyn_testpeer) replays the recorded real-MBDyn 1.7.3 runs of `external modal`
(tests/data/mbdyn-ext/modal_body, README there): given the loads the recording peer answered,
message by message, it must send the kinematics the real MBDyn sent (modal node x, R, v, w, then
q, q'), to <= 1e-12 of each field's largest value over the run (command bytes and order exactly).
The model is modal_body/loose.mbd: a free modal body (MBDyn's `modal` joint with body.fem, 3 FEM
nodes, 2 modes, on a modal node moving at v0 = (0, 0, 0.1), w0 = (0, 0, 0.2), q0 = (0.02, -0.01)),
played by `mbdyn_testpeer --modal-fem body.fem ...` (coupling/testpeer/free_modal_body_model.h:
MBDyn's inertia invariants from the lumped masses, its modal-joint equations, crank nicolson with
its Cayley-Gibbs-Rodrigues rotation increments, and its Newton iterations with its own approximate
Jacobian, so that the tight run's iterates are MBDyn's). The rigid rotation is coupled to the modes
(w_x goes from 0 to 7.8e-3 in the first step through the invariant I5). Runs: the whole loose run
(every message; each message carries the node's prediction and the modal states of the previous
step's last residual) and the first 100 steps of the tight run, every iterate (the modal states one
iterate behind the node's); in the loose run also the converged q, q', q'' of every step (q'' never
crosses the socket) against MBDyn's .mod output."""
import csv
import gzip
import os
import socket
import struct
import subprocess
import time

import pytest

from test_fix_mbdyn import PEER, sockdir  # noqa: F401 (fixture)
from test_mbdyn_ext_replay import recv_exact

pytestmark = pytest.mark.skipif(PEER is None, reason="needs the mbdyn_testpeer executable (build it)")

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "modal_body")
KIN, LOADS = "=22d", "=8d"  # type all, 2 modes
FIELDS = [("x", 0, 3), ("R", 3, 12), ("v", 12, 15), ("w", 15, 18), ("q", 18, 20), ("q'", 20, 22)]
# loose.mbd / tight.mbd: the modal joint, its node and MBDyn's solver settings
MODEL = ["--modal-fem", os.path.join(DATA, "body.fem"), "--modal-origin", "1",
         "--modal-node", "0,0,0,0,0,0.1,0,0,0.2", "--modal-initial", "0.02,0,-0.01,0",
         "--dt", "0.002", "--tolerance", "1e-9", "--max-iterations", "30"]


def read(name):
    with gzip.open(os.path.join(DATA, name), "rt") as f:
        return [(int(r["seq"]), r["dir"], int(r["cmd"]), r["values"].split()) for r in csv.DictReader(f)]


def replay(sock, rows):
    """Plays the recording peer's side against the listening test peer: [(seq, cmd, values)] received."""
    for _ in range(400):
        try:
            s = socket.socket(socket.AF_UNIX)
            s.connect(sock)
            break
        except OSError:
            s.close()
            time.sleep(0.025)
    s.settimeout(60)
    got = []
    try:
        for seq, d, cmd, vals in rows:
            if d == "peer->mbdyn":
                if cmd == 7:
                    s.sendall(struct.pack("=BII", 7, int(vals[0]), int(vals[1])))
                else:
                    s.sendall(bytes([cmd]) + struct.pack(LOADS, *[float(v) for v in vals]))
            else:
                c = recv_exact(s, 1)[0]
                body = recv_exact(s, struct.calcsize(KIN)) if c in (2, 6) else b""
                got.append((seq, c, list(struct.unpack(KIN, body)) if body else []))
    finally:
        s.close()
    return got


# transcript -> (coupling, MBDyn steps in it, kinematics messages)
RUNS = {"transcript_loose_full.csv.gz": ("loose", 500, 501),
        "transcript_tight_first100.csv.gz": ("tight", 100, 776)}


@pytest.mark.parametrize("transcript", sorted(RUNS))
def test_test_peer_replays_the_recorded_modal_run(transcript, sockdir):  # noqa: F811
    coupling, steps, messages = RUNS[transcript]
    rows = read(transcript)
    sock, traj = os.path.join(sockdir, "p.sock"), os.path.join(sockdir, "traj.txt")
    peer = subprocess.Popen([PEER, "--path", sock, "--accept-timeout", "30", "--io-timeout", "30"] + MODEL +
                            ["--coupling", coupling, "--steps", str(steps), "--trajectory", traj],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    t0 = time.monotonic()
    try:
        got = replay(sock, rows)
        out, _ = peer.communicate(timeout=60)
    finally:
        if peer.poll() is None:
            peer.kill()
    secs = time.monotonic() - t0
    assert peer.returncode == 0, out
    want = [(seq, c, v) for seq, d, c, v in rows if d == "mbdyn->peer"]
    assert [(s, c) for s, c, _ in got] == [(s, c) for s, c, _ in want]
    data = [(g, [float(x) for x in w]) for (_, c, g), (_, _, w) in zip(got, want) if c in (2, 6)]
    assert len(data) == messages  # loose: t0 and every prediction; tight: every prediction and iterate
    report, worst_all = [], 0.0
    for name, a, b in FIELDS:
        scale = max(max(abs(x) for x in w[a:b]) for _, w in data)
        worst = max(max(abs(x - y) for x, y in zip(g[a:b], w[a:b])) for g, w in data) / scale
        report.append(f"{name} {worst:.1e}")
        worst_all = max(worst_all, worst)
    print(f"{transcript}: {len(data)} kinematics messages in {secs:.1f} s; worst deviation per field "
          f"(relative to its largest value): {', '.join(report)}")
    assert worst_all <= 1e-12, report
    if coupling == "loose":  # q'' never crosses the socket: the converged steps against MBDyn's .mod
        with gzip.open(os.path.join(DATA, "loose.mod.gz"), "rt") as f:
            mod = [[float(x) for x in line.split()[1:]] for line in f]
        with open(traj) as f:
            mine = [[float(x) for x in line.split()[19:]] for line in f if not line.startswith("#")]
        assert len(mod) == 2 * len(mine) == 2 * (steps + 1)
        for c, name in enumerate(["q", "q'", "q''"]):
            want_c = [mod[2 * k + m][c] for k in range(1, steps + 1) for m in range(2)]
            got_c = [mine[k][3 * m + c] for k in range(1, steps + 1) for m in range(2)]
            worst = max(abs(x - y) for x, y in zip(got_c, want_c)) / max(abs(x) for x in want_c)
            print(f"converged {name} against loose.mod: {worst:.1e}")
            assert worst <= 1e-12, name


def test_modal_body_refuses_a_type_modal_negotiation(sockdir):  # noqa: F811
    """MBDyn's check: the peer asks for the modal part only (07|1|2), the element exchanges all: 05."""
    sock = os.path.join(sockdir, "n.sock")
    peer = subprocess.Popen([PEER, "--path", sock, "--accept-timeout", "30", "--io-timeout", "30"] + MODEL,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        for _ in range(400):
            try:
                s = socket.socket(socket.AF_UNIX)
                s.connect(sock)
                break
            except OSError:
                s.close()
                time.sleep(0.025)
        s.settimeout(30)
        s.sendall(struct.pack("=BII", 7, 1, 2))
        answer = recv_exact(s, 1)
        s.close()
        out, _ = peer.communicate(timeout=30)
    finally:
        if peer.poll() is None:
            peer.kill()
    assert answer == b"\x05" and peer.returncode == 1, (answer, out)
    assert "reference node configuration mismatch (local=yes, remote=no)" in out, out


def fem_variant(tmp_path, drop=None, add=""):
    """body.fem without one record group, or with extra text before END OF FILE."""
    text = open(os.path.join(DATA, "body.fem")).read()
    if drop:
        head, rest = text.split(f"** RECORD GROUP {drop},", 1)
        text = head + "**" + rest.split("\n**\n", 1)[1]
    text = text.replace("** END OF FILE", add + "** END OF FILE")
    p = tmp_path / f"without{drop}.fem" if drop else tmp_path / "extra.fem"
    p.write_text(text)
    return str(p)


@pytest.mark.parametrize("case,message", [
    ("missing", "--modal-fem: cannot open the modal FEM file"),
    ("no11", "RECORD GROUP 11 missing"),
    ("record12", "RECORD GROUP 12 (given inertia or invariants) is not supported"),
    ("origin", "--modal-origin: FEM node \"9\" is not in"),
    ("initial", "--modal-initial expects q, q' for each mode"),
    ("node", "--modal-node expects x,y,z,vx,vy,vz,wx,wy,wz"),
    ("alone", "--modal-origin, --modal-node and --modal-initial need --modal-fem"),
    ("coupling", "the free modal body peer is loose or tight"),
])
def test_modal_body_usage_errors(case, message, sockdir, tmp_path):  # noqa: F811
    fem = os.path.join(DATA, "body.fem")
    args = {"missing": ["--modal-fem", fem + ".nope"],
            "no11": ["--modal-fem", fem_variant(tmp_path, drop=11)],
            "record12": ["--modal-fem", fem_variant(tmp_path, add="** RECORD GROUP 12, GLOBAL INERTIA\n3.\n")],
            "origin": ["--modal-fem", fem, "--modal-origin", "9"],
            "initial": ["--modal-fem", fem, "--modal-initial", "0.02,0,-0.01"],
            "node": ["--modal-fem", fem, "--modal-node", "0,0,0"],
            "alone": ["--modal-origin", "1"],
            "coupling": ["--modal-fem", fem, "--coupling", "none"]}[case]
    p = subprocess.run([PEER, "--path", os.path.join(sockdir, "u.sock")] + args, capture_output=True, text=True,
                       timeout=30)
    assert p.returncode == 2 and message in p.stderr, (p.returncode, p.stderr)
