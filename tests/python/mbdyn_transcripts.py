"""Recorded real-MBDyn 1.7.3 runs (tests/data/mbdyn, README there): transcripts of every protocol
message, node-1 trajectories, and two socket players that replay one side of a transcript:
`replay_peer_side` plays LAMMPS' side (the recorded loads) against a test peer and collects what it
sends; `FakeMbdyn` plays MBDyn's side (the recorded kinematics) against fix mbdyn and collects the
loads it answers. Both compare nothing themselves: the tests do."""
import csv
import gzip
import os
import socket
import struct
import threading
import time

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn")


def data_path(name):
    return os.path.join(DATA, name)


def read_transcript(name):
    """[(seq, direction, cmd, [values])], direction 'mbdyn->peer' or 'peer->mbdyn'."""
    rows = []
    with gzip.open(data_path(name), "rt") as f:
        for r in csv.DictReader(f):
            vals = r["values"].split() if r["values"] else []
            rows.append((int(r["seq"]), r["dir"], int(r["cmd"]), vals))
    return rows


def read_mov(name):
    """Node 1: [[x, y, z, vx, vy, vz]] from t0 on."""
    with gzip.open(data_path(name), "rt") as f:
        return [[float(v) for v in l.split()] for l in f if l.strip() and not l.startswith("#")]


def rel_vec_dev(a, b):
    """max |a - b| over the components, relative to |b| (absolute below 1e-300)."""
    n = max(abs(v) for v in b)
    return max(abs(x - y) for x, y in zip(a, b)) / (n if n > 1e-300 else 1.0)


def _recv_exact(s, n):
    buf = b""
    while len(buf) < n:
        chunk = s.recv(n - len(buf))
        if not chunk:
            raise ConnectionError(f"peer closed after {len(buf)} of {n} bytes")
        buf += chunk
    return buf


def _connect_unix(path, timeout):
    t_end = time.monotonic() + timeout
    while True:
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            s.connect(path)
            return s
        except (FileNotFoundError, ConnectionRefusedError):
            s.close()
            if time.monotonic() > t_end:
                raise
            time.sleep(0.05)


def replay_peer_side(path, transcript, timeout=120):
    """Connects to a listening test peer and plays the peer's recorded messages. Returns the
    kinematics received [(seq, cmd, values)] and the final command byte from MBDyn's side."""
    s = _connect_unix(path, timeout)
    s.settimeout(timeout)
    got = []
    try:
        for seq, d, cmd, vals in transcript:
            if d == "peer->mbdyn":
                if cmd == 7:
                    s.sendall(struct.pack("=BII", 7, int(vals[0]), int(vals[1])))
                else:
                    payload = struct.pack(f"={len(vals)}d", *map(float, vals)) if cmd in (2, 6) else b""
                    s.sendall(bytes([cmd]) + payload)
            else:
                c = _recv_exact(s, 1)[0]
                if c in (2, 6):
                    payload = _recv_exact(s, 8 * len(vals))
                    got.append((seq, c, list(struct.unpack(f"={len(vals)}d", payload))))
                else:
                    got.append((seq, c, []))
    finally:
        s.close()
    return got


class FakeMbdyn:
    """Listens on a Unix socket like MBDyn `create, yes` and plays the recorded kinematics; records
    the peer's answers [(seq, cmd, values)] in place of the recorded ones."""

    def __init__(self, path, transcript, timeout=120):
        self.path, self.transcript, self.timeout = path, transcript, timeout
        self.answers, self.error = [], None
        self.srv = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.srv.bind(path)
        self.srv.listen(1)
        self.srv.settimeout(timeout)
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        conn = None
        try:
            conn, _ = self.srv.accept()
            conn.settimeout(self.timeout)
            for seq, d, cmd, vals in self.transcript:
                if d == "mbdyn->peer":
                    payload = struct.pack(f"={len(vals)}d", *map(float, vals)) if cmd in (2, 6) else b""
                    conn.sendall(bytes([cmd]) + payload)
                elif cmd == 7:
                    req = _recv_exact(conn, 9)
                    self.answers.append((seq, req[0], list(struct.unpack("=II", req[1:]))))
                else:
                    c = _recv_exact(conn, 1)[0]
                    n = len(vals) if c in (2, 6) else 0
                    payload = _recv_exact(conn, 8 * n) if n else b""
                    self.answers.append((seq, c, list(struct.unpack(f"={n}d", payload)) if n else []))
        except Exception as e:  # reported by the test
            self.error = repr(e)
        finally:
            if conn:
                conn.close()
            self.srv.close()
            try:
                os.unlink(self.path)
            except OSError:
                pass

    def join(self):
        self.thread.join(self.timeout)
        return self.answers
