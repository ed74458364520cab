"""The test peer (mbdyn_testpeer) replays the recorded real-MBDyn 1.7.3 runs of `external structural
mapping` on the cantilever of tests/data/mbdyn-ext/mapping_beam (README there): given the loads the
recording peer answered, message by message, it must send the kinematics the real MBDyn sent (the
15 mapped points' positions q and velocities q'), to <= 1e-12 of each field's largest value over
the run (1e-12 asked; the measured floor, set by round-off in the beam's axial force, is below),
and the same command bytes in the same order.
The model is mapping_beam/loose.mbd: node 0 static and clamped, nodes 1..3 dynamic with a body of
mass 0.1 and inertia diag(1e-3), three beam2 elements (`linear elastic generic, diag, 1e6, 1e5,
1e5, 50, 100, 100`), gravity 9.81 along -z, crank nicolson, tolerance 1e-9, the 12 offset points
mapped by mapping.dat; played by `mbdyn_testpeer --cantilever ... --mapping ...`
(coupling/testpeer/cantilever_model.h: MBDyn's equations, beam2 residual and Jacobian, predictor
and Newton updates). Runs: the whole loose run (500 steps; only predictions are sent, so this
checks the converged states) and the first 100 steps of the tight run, every iterate (each is
sent after one of MBDyn's Newton updates, so this checks the Jacobian too)."""
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

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "mapping_beam")
M = 15  # mapped points
MODEL = ["--cantilever", "3,1.5,0.1,1e-3,1e6,1e5,50,100",
         "--beam-offset", "0,-0.1,0", "--beam-offset", "0,0,0", "--beam-offset", "0,0.1,0",
         "--mapping", os.path.join(DATA, "mapping.dat"), "--mapped-points", str(M),
         "--gravity", "0,0,-9.81", "--dt", "0.002", "--tolerance", "1e-9", "--max-iterations", "30"]
# fields: value indices of a kinematics message (q, then q'; x y z per mapped point)
FIELDS = [("q", list(range(3 * M))),
          ("q' along the beam", [3 * M + 3 * j for j in range(M)]),
          ("q' across", [3 * M + 3 * j + a for j in range(M) for a in (1, 2)])]


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
                    s.sendall(bytes([cmd]) + struct.pack(f"={3 * M}d", *map(float, vals)))
            else:
                c = recv_exact(s, 1)[0]
                body = recv_exact(s, 8 * 6 * M) if c in (2, 6) else b""
                got.append((seq, c, list(struct.unpack(f"={6 * M}d", body)) if body else []))
    finally:
        s.close()
    return got


# transcript -> (coupling, MBDyn steps in it, kinematics messages, tolerance per field). Measured (each
# field relative to the largest |q| or |q'| over the run): loose q 5.3e-15, q' along 7.5e-12, across
# 2.8e-12; tight q 1.3e-15, q' along 2.6e-12, across 5.6e-14. The floor is round-off: the axial strain
# R^T x' - L0 of a beam2 is a difference of numbers near 1, so with EA = 1e6 its force carries
# 1e-10 of noise, the residuals MBDyn stops at are 1e-10..1e-9, and over a 2 ms step the noise
# moves the axial velocities by 1e-14..1e-12 (the two programs round differently: their linear
# solvers differ); the velocities across the beam and the positions follow MBDyn to 1e-13 and 1e-14.
RUNS = {"transcript_loose_full.csv.gz": ("loose", 500, 501, (1e-14, 1e-11, 5e-12)),
        "transcript_tight_first100.csv.gz": ("tight", 100, 687, (1e-14, 5e-12, 1e-13))}


@pytest.mark.parametrize("transcript", sorted(RUNS))
def test_test_peer_replays_the_recorded_mapping_run(transcript, sockdir):  # noqa: F811
    coupling, steps, messages, tolerances = RUNS[transcript]
    rows = read(transcript)
    sock = os.path.join(sockdir, "m.sock")
    args = MODEL + ["--coupling", coupling, "--steps", str(steps)]
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
    scale = {"q": max(abs(x) for _, w in data for x in w[:3 * M]),
             "q'": max(abs(x) for _, w in data for x in w[3 * M:])}
    report, failed = [], []
    for (name, idx), tol in zip(FIELDS, tolerances):
        worst = max(abs(g[i] - w[i]) for g, w in data for i in idx) / scale[name.split()[0]]
        report.append(f"{name} {worst:.1e}")
        if not worst <= tol:
            failed.append(f"{name} {worst:.1e} > {tol:.0e}")
    print(f"{transcript}: {len(data)} kinematics messages in {secs:.1f} s; worst deviation per field "
          f"(relative to the largest |q| or |q'|): {', '.join(report)}")
    assert not failed, failed


def test_mapping_peer_usage_errors(sockdir, tmp_path):  # noqa: F811
    bad = tmp_path / "bad.dat"
    bad.write_text("# 45 x 36\n1 1 1.0\n46 1 1.0\n")
    cases = [
        (["--cantilever", "3,1.5,0.1"], "--cantilever expects n,L,m,J,EA,GA,GJ,EI"),
        (["--cantilever", "2.5,1.5,0.1,1e-3,1e6,1e5,50,100"], "n a whole number of elements"),
        (["--beam-offset", "0,0,0"], "--beam-offset and --mapping need --cantilever"),
        (MODEL[:2] + MODEL[8:], "needs at least one --beam-offset"),
        (MODEL[:8], "needs --mapping FILE and --mapped-points M"),
        (MODEL[:9] + [str(bad)] + MODEL[10:], "bad.dat:3: expected `row col value` with row 1..45, col 1..36"),
        (MODEL[:9] + [str(tmp_path / "none.dat")] + MODEL[10:], "cannot open mapping file"),
        (MODEL + ["--coupling", "none"], "the mapping peer is loose or tight"),
    ]
    for args, message in cases:
        p = subprocess.run([PEER, "--path", os.path.join(sockdir, "u.sock")] + args, capture_output=True, text=True,
                           timeout=30)
        assert p.returncode == 2 and message in p.stderr, (args, p.returncode, p.stderr)
