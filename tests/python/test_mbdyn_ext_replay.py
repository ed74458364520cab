"""The test peer (mbdyn_testpeer) replays the recorded real-MBDyn 1.7.3 runs of `external structural`
with a reference node (tests/data/mbdyn-ext/refnode_forces, README there): given the loads the
recording peer answered, message by message, it must send the kinematics the real MBDyn sent, to
<= 1e-12 of each field's largest value over the run (labels and command bytes exactly).
The model is refnode_forces/loose.mbd: the reference node and three points are free rigid bodies
(MBDyn dynamic nodes, a body of isotropic inertia each, gravity 1 along -z), played by
`mbdyn_testpeer --reference-body ... --point-body ...` (MBDyn's crank nicolson on the nodes'
momenta with its Cayley-Gibbs-Rodrigues rotation increments; coupling/testpeer/free_bodies_model.h).
Runs: the loose run (every message); the loose run whose peer answered the point loads in a
rotated label order, which MBDyn's `sorted, no` applies with the inverse permutation: the peer
must reproduce that bug too (its trajectory leaves the correct one by 0.14; with the labels
applied as sent it misses this recording by 8.7 of a field's largest value); and the first 50
steps of the tight run, every iterate (MBDyn's Newton updates: the external loads without a
Jacobian, v x B and the rotation rate linearised at the iterate)."""
import csv
import gzip
import os
import socket
import struct
import subprocess
import time

import pytest

from test_fix_mbdyn import PEER, sockdir  # noqa: F401 (fixture)

pytestmark = pytest.mark.skipif(PEER is None, reason="needs the mbdyn_testpeer executable (build it)")

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "refnode_forces")
KIN, LOADS = "=2I18d4I54d", "=2I6d4I18d"  # the wire layouts (3 points, labels, matrices, reference node)
# value index ranges of a kinematics message, per field
KIN_FIELDS = [("x_r", 2, 5), ("R_r", 5, 14), ("v_r", 14, 17), ("w_r", 17, 20), ("x~", 24, 33), ("R~", 33, 60),
              ("v~", 60, 69), ("w~", 69, 78)]
# loose.mbd: m, J, x0, v0, w0 of the reference node 10 and of the points 20, 30, 40
BODIES = ["--reference-body", "1,0.1,0,0,0,0.1,0,0,0,0,0.5",
          "--point-body", "0.2,0.01,1,0,0,0.1,0.5,0.05,0,0,0.5",
          "--point-body", "0.2,0.01,0,1,0,-0.4,0,0,0,0,0.5",
          "--point-body", "0.2,0.01,0,0,1,0.1,0,0,0,0,0.5",
          "--reference-label", "10", "--point-labels", "20,30,40", "--gravity", "0,0,-1",
          "--dt", "0.002"]


def read(name):
    with gzip.open(os.path.join(DATA, name), "rt") as f:
        return [(int(r["seq"]), r["dir"], int(r["cmd"]), r["values"].split()) for r in csv.DictReader(f)]


def recv_exact(s, n):
    buf = b""
    while len(buf) < n:
        chunk = s.recv(n - len(buf))
        if not chunk:
            raise ConnectionError(f"the test peer closed after {len(buf)} of {n} bytes")
        buf += chunk
    return buf


def pack(fmt, vals):
    codes = []
    num = ""
    for ch in fmt[1:]:
        if ch.isdigit():
            num += ch
        else:
            codes += [ch] * int(num or 1)
            num = ""
    return struct.pack(fmt, *[int(v) if c == "I" else float(v) for c, v in zip(codes, vals)])


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
                    s.sendall(bytes([cmd]) + pack(LOADS, vals))
            else:
                c = recv_exact(s, 1)[0]
                body = recv_exact(s, struct.calcsize(KIN)) if c in (2, 6) else b""
                got.append((seq, c, list(struct.unpack(KIN, body)) if body else []))
    finally:
        s.close()
    return got


# transcript -> (coupling, MBDyn steps in it, kinematics messages)
RUNS = {"transcript_loose_full.csv.gz": ("loose", 200, 201),
        "transcript_loose_permuted.csv.gz": ("loose", 200, 201),
        "transcript_tight_first50.csv.gz": ("tight", 50, 251)}


@pytest.mark.parametrize("transcript", sorted(RUNS))
def test_test_peer_replays_the_recorded_refnode_run(transcript, sockdir):  # noqa: F811
    coupling, steps, messages = RUNS[transcript]
    rows = read(transcript)
    sock = os.path.join(sockdir, "p.sock")
    args = BODIES + ["--coupling", coupling, "--steps", str(steps)]
    peer = subprocess.Popen([PEER, "--path", sock, "--accept-timeout", "30", "--io-timeout", "30"] + args,
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
    assert len(data) == messages  # loose: t0 and every step; tight: t0, then every prediction and iterate
    for g, w in data:  # reference label, pad, point labels, pad
        assert [int(x) for x in g[0:2] + g[20:24]] == [int(x) for x in w[0:2] + w[20:24]] == [10, 0, 20, 30, 40, 0]
    report, worst_all = [], 0.0
    for name, a, b in KIN_FIELDS:
        scale = max(max(abs(x) for x in w[a:b]) for _, w in data)
        worst = max(max(abs(x - y) for x, y in zip(g[a:b], w[a:b])) for g, w in data) / scale
        report.append(f"{name} {worst:.1e}")
        worst_all = max(worst_all, worst)
    print(f"{transcript}: {len(data)} kinematics messages in {secs:.1f} s; worst deviation per field "
          f"(relative to its largest value): {', '.join(report)}")
    assert worst_all <= 1e-12, report


@pytest.mark.parametrize("args,message", [
    (["--reference-body", "1,0.1,0,0,0"], "--reference-body expects m,J,x,y,z,vx,vy,vz,wx,wy,wz"),
    (["--reference-body", "0,0.1,0,0,0,0,0,0,0,0,0"], "with m, J > 0"),
    (["--point-body", "1,0.1,0,0,0,0,0,0,0,0,0"], "--point-body needs --reference-body"),
    (["--reference-body", "1,0.1,0,0,0,0,0,0,0,0,0"], "needs at least one --point-body"),
    (BODIES + ["--point-labels", "20,30"], "--point-labels needs one label per --point-body"),
    (BODIES + ["--coupling", "none"], "the free-bodies peer is loose or tight"),
])
def test_free_bodies_usage_errors(args, message, sockdir):  # noqa: F811
    p = subprocess.run([PEER, "--path", os.path.join(sockdir, "u.sock")] + args, capture_output=True, text=True,
                       timeout=30)
    assert p.returncode == 2 and message in p.stderr, (p.returncode, p.stderr)
