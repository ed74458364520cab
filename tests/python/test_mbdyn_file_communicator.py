"""fix mbdyn over MBDyn's file communicator (`fix mbdyn file IN OUT`), driven by the OUT files the
real MBDyn 1.7.3 wrote in a recorded spring-mass run (tests/data/mbdyn-ext/file_communicator:
`"IN.dat", unlink, "OUT.dat", no clobber, ..., precision, 16`, `send after predict, no`, 25 steps):
a player writes each recorded OUT as MBDyn does (OUT.dat.tmp renamed to OUT.dat, only once the
previous OUT is gone: `no clobber`) and takes each IN the fix writes (then removes it: `unlink`).
The split spring-mass deck (k = 50, c = 0.4 in LAMMPS, the recording peer's law) must answer the
recorded IN files to <= 1e-12 of the largest force. Also: the fix never overwrites an IN it finds,
times out naming the file, and every new keyword's bad value is an ERROR naming it. And the test
peer's file mode (MBDyn's side), given the recorded IN files, writes the recorded OUT files."""
import os
import re
import subprocess
import threading
import time

import pytest

from dembridge import plugin_path
from test_fix_mbdyn import PEER, error_line, run_lammps, spring_mass_deck

pytestmark = pytest.mark.skipif(not os.path.exists(plugin_path()), reason="needs the plugin (build dembridgeplugin)")

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "file_communicator")


def read_sequence(name="file_sequence.txt"):
    """[(kind 'OUT' | 'IN', index, text)] in the recorded order."""
    parts = re.split(r"^=== (OUT|IN)\.(\d+) ===\n", open(os.path.join(DATA, name)).read(), flags=re.M)
    return [(parts[i], int(parts[i + 1]), parts[i + 2]) for i in range(1, len(parts), 3)]


def numbers(text):
    return [float(w) for l in text.splitlines() if l.strip() and not l.startswith("#") for w in l.split()]


class RecordedMbdynFiles(threading.Thread):
    """Plays MBDyn's side of the file communicator from the recorded OUT files."""

    def __init__(self, folder, outs, timeout=60):
        super().__init__(daemon=True)
        self.folder, self.outs, self.timeout = folder, outs, timeout
        self.ins, self.error = [], None
        self.start()

    def wait(self, ready, what):
        t_end = time.monotonic() + self.timeout
        while not ready():
            if time.monotonic() > t_end:
                raise TimeoutError(what)
            time.sleep(0.001)

    def run(self):
        out, inp = os.path.join(self.folder, "OUT.dat"), os.path.join(self.folder, "IN.dat")
        try:
            for text in self.outs:
                self.wait(lambda: not os.path.exists(out), "the fix never removed OUT.dat")  # no clobber
                open(out + ".tmp", "w").write(text)
                os.rename(out + ".tmp", out)
                self.wait(lambda: os.path.exists(inp), "the fix never wrote IN.dat")
                self.ins.append(open(inp).read())
                os.unlink(inp)  # unlink
        except Exception as e:  # reported by the test
            self.error = repr(e)


def file_deck(folder, steps, extra=""):
    return spring_mass_deck("X", 0.004, 1, steps).replace(
        "path X", f"file {folder}/IN.dat {folder}/OUT.dat sleep 0.002 precision 16").replace(
        "connect_timeout 20 io_timeout 20", f"io_timeout 20 {extra}")


@pytest.fixture
def folder(tmp_path):
    return str(tmp_path)


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_fix_mbdyn_answers_the_recorded_in_files(folder, nprocs):
    seq = read_sequence()
    outs = [t for k, _, t in seq if k == "OUT"]
    expected = [numbers(t) for k, _, t in seq if k == "IN"]
    assert len(outs) == len(expected) == 27
    player = RecordedMbdynFiles(folder, outs)
    t0 = time.monotonic()
    rc, out, _ = run_lammps(file_deck(folder, len(outs) - 1), folder, nprocs=nprocs, timeout=120)
    player.join(60)
    secs = time.monotonic() - t0
    assert player.error is None, (player.error, out[-3000:])
    assert rc == 0, out[-3000:]
    got = [numbers(t) for t in player.ins]
    assert [len(g) for g in got] == [3] * 27
    scale = max(abs(v) for e in expected for v in e)
    worst = max(abs(a - b) for g, e in zip(got, expected) for a, b in zip(g, e))
    print(f"file communicator, {nprocs} rank(s): {len(got)} IN files in {secs:.2f} s, worst deviation from the recorded IN "
          f"{worst / scale:.1e} of the largest force {scale}")
    assert worst <= 1e-12 * scale
    assert not os.path.exists(os.path.join(folder, "IN.dat.tmp"))


@pytest.mark.parametrize("name", ["IN.dat", "IN.dat.tmp"])
def test_existing_in_file_is_refused_and_kept(folder, name):
    path = os.path.join(folder, name)
    open(path, "w").write("a user's file\n")
    rc, out, _ = run_lammps(file_deck(folder, 2), folder, timeout=60)
    assert rc != 0
    assert f"{name} already exists" in error_line(out), error_line(out)
    assert open(path).read() == "a user's file\n"


def test_missing_out_file_times_out_naming_it(folder):
    t0 = time.monotonic()
    rc, out, _ = run_lammps(file_deck(folder, 2).replace("io_timeout 20", "io_timeout 0.3"), folder, timeout=60)
    assert rc != 0
    err = error_line(out)
    assert "MBDyn wrote no " + os.path.join(folder, "OUT.dat") in err, err
    assert time.monotonic() - t0 < 20


BAD = {
    "file_one_name": ("file {d}/IN.dat {d}/OUT.dat sleep 0.002 precision 16 node", "file {d}/IN.dat",
                      ["keyword 'file' expects MBDyn's output file OUT", "but the command ends there"], True),
    "file_and_path": ("io_timeout 20", "io_timeout 20 path x.sock", ["give exactly one communicator"], False),
    "same_files": ("{d}/OUT.dat sleep", "{d}/IN.dat sleep", ["IN and OUT are the same file"], False),
    "sleep_zero": ("sleep 0.002", "sleep 0", ["keyword 'sleep' expects seconds (> 0)", "0"], False),
    "sleep_word": ("sleep 0.002", "sleep soon", ["keyword 'sleep' expects seconds (> 0)", "'soon'"], False),
    "precision_big": ("precision 16", "precision 40", ["keyword 'precision' expects digits (1 to 17)", "40"], False),
    "precision_word": ("precision 16", "precision high", ["keyword 'precision' expects digits (1 to 17)", "'high'"], False),
    "file_tight": ("io_timeout 20", "io_timeout 20 coupling tight", ["'file IN OUT' supports coupling loose only"], False),
    "file_predictor": ("io_timeout 20", "io_timeout 20 predictor correct",
                       ["'predictor correct' needs a socket", "converged states"], False),
    "file_refnode": ("io_timeout 20", "io_timeout 20 reference_node yes", ["'file IN OUT' does not support 'reference_node yes'"], False),
    "sleep_without_file": ("file {d}/IN.dat {d}/OUT.dat sleep 0.002 precision 16", "path x.sock sleep 1",
                           ["'sleep' and 'precision' are for the file communicator"], False),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_file_keywords_bad_input(case, folder):
    old, new, expect, truncate = BAD[case]
    old, new = old.format(d=folder), new.format(d=folder)
    deck = file_deck(folder, 2)
    assert old in deck
    if truncate:  # the command ends right after the replacement
        line = next(l for l in deck.splitlines() if l.startswith("fix M all mbdyn"))
        deck = deck.replace(line, line[:line.index(old)] + new)
    else:
        deck = deck.replace(old, new, 1)
    rc, out, secs = run_lammps(deck, folder, timeout=60)
    err = error_line(out)
    assert rc != 0
    assert "Fix mbdyn (id M)" in err, out[-2000:]
    for e in expect:
        assert e in err, err
    assert secs < 15


@pytest.mark.parametrize("text,expect", [
    ("# regular nodes\n0.1 0 0 0 0\n", "OUT.dat line 2: expected 6 values (x y z v(3)), found 5"),
    ("# regular nodes\n0.1 0 0 nan 0 0\n", "OUT.dat line 2: v expects a finite number, got 'nan'"),
    ("# regular nodes\n", "OUT.dat: expected 1 point line(s) (x y z v(3)), found 0"),
])
def test_malformed_out_file_is_an_error_naming_file_and_line(folder, text, expect):
    RecordedMbdynFiles(folder, [text], timeout=2)  # it then waits for an answer that never comes
    rc, out, _ = run_lammps(file_deck(folder, 2), folder, timeout=60)
    err = error_line(out)
    assert rc != 0
    assert "Fix mbdyn (id M)" in err and expect in err, err


@pytest.mark.skipif(PEER is None, reason="needs the mbdyn_testpeer executable (build it)")
def test_test_peer_file_mode_replays_the_recorded_out_files(folder):
    seq = read_sequence()
    outs = [numbers(t) for k, _, t in seq if k == "OUT"]
    ins = [t for k, _, t in seq if k == "IN"]
    out, inp = os.path.join(folder, "OUT.dat"), os.path.join(folder, "IN.dat")
    peer = subprocess.Popen([PEER, "--file-in", inp, "--file-out", out, "--nodes", "1", "--orientation", "none",
                             "--steps", "25", "--dt", "0.004", "--mass", "2", "--x0", "0.1,0,0", "--v0", "0,0,0",
                             "--tolerance", "1e-9", "--derivatives-tolerance", "1e-6", "--io-timeout", "20"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    got = []
    try:
        for text in ins:  # the recording peer's side: read OUT, remove it, answer IN (tmp + rename)
            t_end = time.monotonic() + 20
            while not os.path.exists(out):
                assert time.monotonic() < t_end and peer.poll() is None, "the test peer wrote no OUT.dat"
                time.sleep(0.001)
            got.append(numbers(open(out).read()))
            os.unlink(out)
            open(inp + ".tmp", "w").write(text)
            os.rename(inp + ".tmp", inp)
        log, _ = peer.communicate(timeout=20)
    finally:
        if peer.poll() is None:
            peer.kill()
    assert peer.returncode == 0, log
    assert len(got) == len(outs) == 27
    xs = max(abs(v) for o in outs for v in o[0:3])
    vs = max(abs(v) for o in outs for v in o[3:6])
    worst = max(max(max(abs(a - b) for a, b in zip(g[0:3], o[0:3])) / xs,
                    max(abs(a - b) for a, b in zip(g[3:6], o[3:6])) / vs) for g, o in zip(got, outs))
    print(f"test peer file mode: 27 OUT files, worst deviation from the recorded ones {worst:.1e} of each field's largest value")
    assert worst <= 1e-12
    assert os.path.exists(inp)  # the last answer is never read, as with MBDyn


@pytest.mark.skipif(PEER is None, reason="needs the mbdyn_testpeer executable (build it)")
def test_coupled_over_files_reproduces_the_real_mbdyn_trajectory(folder):
    """fix mbdyn and the test peer coupled over the two files, neither side waiting in lockstep: the
    peer's node trajectory equals the real MBDyn's file.mov of the recorded run."""
    out, inp = os.path.join(folder, "OUT.dat"), os.path.join(folder, "IN.dat")
    traj = os.path.join(folder, "traj.txt")
    peer = subprocess.Popen([PEER, "--file-in", inp, "--file-out", out, "--nodes", "1", "--orientation", "none",
                             "--steps", "25", "--dt", "0.004", "--mass", "2", "--x0", "0.1,0,0", "--v0", "0,0,0",
                             "--tolerance", "1e-9", "--derivatives-tolerance", "1e-6", "--io-timeout", "30",
                             "--trajectory", traj], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        rc, lmp_out, secs = run_lammps(file_deck(folder, 26), folder, timeout=120)
        log, _ = peer.communicate(timeout=30)
    finally:
        if peer.poll() is None:
            peer.kill()
    assert rc == 0, lmp_out[-3000:]
    assert peer.returncode == 0, log
    mov = [[float(v) for v in l.split()] for l in open(os.path.join(DATA, "file.mov")) if l.strip()]
    rows = [[float(v) for v in l.split()] for l in open(traj) if not l.startswith("#")]
    assert len(rows) == len(mov) == 26
    # file.mov: label x y z phi(3) v(3) w(3); the trajectory: t x y z v(3) theta theta_dot
    worst = max(max(abs(r[1 + c] - m[1 + c]) for c in range(3)) for r, m in zip(rows, mov))
    worst_v = max(max(abs(r[4 + c] - m[7 + c]) for c in range(3)) for r, m in zip(rows, mov))
    print(f"coupled over files: {secs:.2f} s; max |x - x_MBDyn| {worst:.1e}, max |v - v_MBDyn| {worst_v:.1e}")
    assert worst <= 1e-12 and worst_v <= 1e-12
    assert os.path.exists(inp)  # the answer to MBDyn's last OUT stays unread, as in the recorded run
