"""fix mbdyn against what it must refuse (doc/fix_mbdyn.md, "What MBDyn sends is checked" and
`create no`): a scripted MBDyn (FakeMbdyn, tests/python/mbdyn_transcripts.py) sends an all-zero,
skewed or mirrored orientation matrix, or a position that puts a coupled atom out of the box: an
ERROR naming the node and the field, never LAMMPS's "Lost atoms". With `create no` a stale socket
at the path is removed, while a regular file or a socket somebody listens on is left untouched and
reported."""
import os
import shutil
import socket
import stat
import tempfile

import pytest

from dembridge import plugin_path
from mbdyn_transcripts import FakeMbdyn
from test_fix_mbdyn import PEER, X0, error_line, read_traj, run_create_no, run_lammps, spring_mass_deck

pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")

EYE = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]  # column-major on the wire, as MBDyn sends it
MATRIX_FLAGS = 0x202  # MBC_NODAL | orientation matrix


@pytest.fixture
def sockdir():
    d = tempfile.mkdtemp(prefix="mbc", dir="/tmp")
    yield d
    shutil.rmtree(d, ignore_errors=True)


def kinematics(x, R, v=(0.0, 0.0, 0.0), w=(0.0, 0.0, 0.0)):
    return [repr(float(c)) for c in list(x) + list(R) + list(v) + list(w)]


def script(*messages):
    """MBDyn's side for one point with an orientation matrix: negotiation, then each kinematics
    message (cmd 6) followed by the peer's loads."""
    rows = [(0, "peer->mbdyn", 7, [str(MATRIX_FLAGS), "1"]), (1, "mbdyn->peer", 8, [])]
    for m in messages:
        rows.append((len(rows), "mbdyn->peer", 6, m))
        rows.append((len(rows), "peer->mbdyn", 6, ["0.0"] * 6))
    return rows


def run_against(sockdir, rows, deck_edit=lambda d: d):
    sock = os.path.join(sockdir, "m.sock")
    fake = FakeMbdyn(sock, rows, timeout=30)
    deck = spring_mass_deck(sock, 0.001, 1, 5).replace("orientation none", "orientation matrix")
    rc, out, _ = run_lammps(deck_edit(deck), sockdir, timeout=60)
    fake.join()
    return rc, out


GOOD = kinematics((X0, 0, 0), EYE)
BAD_POSES = {
    "zero_matrix": ([kinematics((X0, 0, 0), [0.0] * 9)], ["node 1 (atom 1): MBDyn's orientation matrix", "is all zero"]),
    "skewed_matrix": ([kinematics((X0, 0, 0), [1.0, 0.0, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0, 1.0])],
                      ["node 1 (atom 1): MBDyn's orientation matrix", "is not orthonormal", "tolerance 1e-06"]),
    "scaled_matrix": ([kinematics((X0, 0, 0), [1.001 * e for e in EYE])], ["is not orthonormal: max |R^T R - I| = 0.002"]),
    "mirror_matrix": ([kinematics((X0, 0, 0), [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0])],
                      ["has determinant -1: a reflection"]),
    "position_outside_box": ([kinematics((5.0, 0, 0), EYE)],
                             ["node 1 (atom 1): MBDyn's position (5, 0, 0)", "puts atom 1 outside the box in x: [-1, 1]"]),
    "absurd_position_later": ([GOOD, kinematics((X0, 0, 1e300), EYE)],
                              ["MBDyn's position (0.1, 0, 1e+300) in the message received at LAMMPS step 1",
                               "outside the box in z"]),
}


@pytest.mark.parametrize("case", sorted(BAD_POSES))
def test_bad_pose_is_an_error_naming_node_and_field(case, sockdir):
    messages, expect = BAD_POSES[case]
    rc, out = run_against(sockdir, script(*messages))
    err = error_line(out)
    assert rc != 0, out[-2000:]
    assert "Lost atoms" not in out
    for e in expect:
        assert e in err, err


def test_group_atom_pushed_out_of_the_box_is_named(sockdir):
    """A rigid group (two atoms 0.5 either side of its point along x): the point at x = 0.6 is in
    the box, but it carries atom 2 to x = 1.1, past the fixed boundary at 1."""
    def two_atoms(deck):
        return (deck.replace("create_atoms 1 single", "create_atoms 1 single -0.5 0 0 units box\n"
                             "create_atoms 1 single 0.5 0 0 units box\ncreate_atoms 1 single")
                .replace("set atom 1 diameter", "group plate id 1 2\nset group all diameter")
                .replace("node atom 1", "node group plate")
                .replace("fix S all spring tether", "fix S plate spring tether"))
    rc, out = run_against(sockdir, script(kinematics((0, 0, 0), EYE), kinematics((0.6, 0, 0), EYE)), two_atoms)
    err = error_line(out)
    assert rc != 0, out[-2000:]
    assert "node 1 (group plate): MBDyn's position (0.6, 0, 0)" in err, err
    assert "puts atom 2 at (1.1, 0, 0) outside the box in x" in err, err


def create_no_deck(sock):
    return spring_mass_deck(sock, 0.004, 1, 20).replace("node atom 1", "create no node atom 1")


def test_create_no_leaves_a_regular_file_at_the_socket_path_untouched(sockdir):
    path = os.path.join(sockdir, "results.txt")
    open(path, "w").write("a user's file\n")
    rc, out, secs = run_lammps(create_no_deck(path), sockdir, timeout=60)
    err = error_line(out)
    assert rc != 0
    assert f"'{path}' exists and is a regular file, not a socket: it is left untouched" in err, err
    assert open(path).read() == "a user's file\n"
    assert secs < 15  # at the fix command, before any wait


def test_create_no_refuses_a_socket_somebody_listens_on(sockdir):
    path = os.path.join(sockdir, "busy.sock")
    other = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    other.bind(path)
    other.listen(1)
    try:
        rc, out, _ = run_lammps(create_no_deck(path), sockdir, timeout=60)
        assert rc != 0
        assert f"another process is listening on the socket '{path}'" in error_line(out), out[-2000:]
        assert stat.S_ISSOCK(os.lstat(path).st_mode)  # still the other process's socket
    finally:
        other.close()


def test_create_no_removes_a_stale_socket_and_runs(sockdir):
    """A socket file nobody listens on (a crashed run's) is removed, LAMMPS listens there and the
    peer connects: the run completes."""
    path = os.path.join(sockdir, "stale.sock")
    dead = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    dead.bind(path)
    dead.close()  # the file stays: nobody listens
    assert stat.S_ISSOCK(os.lstat(path).st_mode)
    assert len(read_traj(run_create_no(sockdir, path, 20))) == 21
