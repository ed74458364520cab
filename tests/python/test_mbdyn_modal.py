"""fix mbdyn ... modal (MBDyn's `external modal`), driven by the kinematics the real MBDyn 1.7.3
sent (tests/data/mbdyn-ext/modal_body): three atoms on the three FEM nodes of body.fem (x axis,
mode 1 along z, mode 2 along y, nodal shape (1, -2, 1)).
- type modal: the recording peer's law p = -kq q - cq qdot (kq = 300, 600, cq = 1, 2) is the deck's
  fix addforce fy = -100 y - vy/3, fz = -50 z - vz/6 on the atoms (sum of w^2 = 6), so fix mbdyn must
  answer the recorded generalized forces.
- type all (and rigid, q = 0): the atoms must sit at x_n + R (X + sum q Phi) of every recorded message,
  and a constant force on atom 3 must come back as F = f, M = (x_3 - x_n) x f, p = Phi(3) . R^T f
  (closed forms here).
- bad input: an ERROR naming what was expected."""
import csv
import os
import shutil
import struct
import tempfile

import pytest

from dembridge import plugin_path
from test_fix_mbdyn import error_line, run_lammps
from test_mbdyn_refnode_forces import RecordedMbdyn

pytestmark = pytest.mark.skipif(not os.path.exists(plugin_path()), reason="needs the plugin (build dembridgeplugin)")

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "modal_body")
FEM = os.path.join(DATA, "body.fem")
W = (1.0, -2.0, 1.0)  # the nodal shape of both modes


def read(name):
    with open(os.path.join(DATA, name)) as f:
        return [(r["dir"], int(r["cmd"]), [float(v) for v in r["values"].split()]) for r in csv.DictReader(f)]


class RecordedModalMbdyn(RecordedMbdyn):
    """Listens like MBDyn `create, yes`, plays the recorded kinematics, collects the answers
    (the refnode test's server with this element's messages)."""

    def __init__(self, path, rows, nloads):
        self.nloads, self.request = nloads, None
        super().__init__(path, rows)

    def run(self):
        try:
            self.play()
        except Exception as e:  # reported by the test
            self.error = repr(e)

    def play(self):
        self.conn, _ = self.srv.accept()
        self.srv.close()
        self.conn.settimeout(60)
        self.request = struct.unpack("=BII", self.recv(9))
        self.conn.sendall(b"\x08")
        for d, cmd, vals in self.rows:
            if d != "mbdyn->peer" or cmd == 8:
                continue
            if cmd == 5:  # MBDyn's end: LAMMPS may already have closed after its last answer
                try:
                    self.conn.sendall(b"\x05")
                except OSError:
                    pass
                break
            self.conn.sendall(bytes([cmd]) + struct.pack(f"={len(vals)}d", *vals))
            c = self.recv(1)[0]
            self.answers.append((c, list(struct.unpack(f"={self.nloads}d", self.recv(8 * self.nloads)))))
        self.conn.close()


DECK = """plugin load ${{plugin}}
units si
atom_style atomic
region box block -2 2 -2 2 -2 2
create_box 1 box
# the three FEM nodes of body.fem, at rest (the modal node at the origin, R = I)
create_atoms 1 single 0.0 0 0 units box
create_atoms 1 single 0.5 0 0 units box
create_atoms 1 single 1.0 0 0 units box
mass 1 1.0
timestep 0.002
{forces}
fix M all mbdyn path {sock} modal {fem} modes 2 origin 1 type {type} connect_timeout 60 io_timeout 60
dump d all custom 1 {dump} id x y z
dump_modify d sort id format float %.17g
run {steps}
"""


def recorded_answers(rows):
    return [(c, v) for d, c, v in rows if d == "peer->mbdyn" and c in (2, 6)]


def read_dump(path):
    frames, lines = [], open(path).read().split("ITEM: TIMESTEP")[1:]
    for block in lines:
        body = block.split("ITEM: ATOMS id x y z")[1].split()
        frames.append([[float(v) for v in body[4 * i + 1:4 * i + 4]] for i in range(3)])
    return frames


@pytest.fixture
def sockdir():
    d = tempfile.mkdtemp(prefix="mbmo", dir="/tmp")
    yield d
    shutil.rmtree(d, ignore_errors=True)


def run_case(sockdir, transcript, type_, nloads, forces, nprocs=1):
    rows = read(transcript)
    steps = len(recorded_answers(rows)) - 1  # the t0 exchange is answered at the run's set-up
    sock, dump = os.path.join(sockdir, "m.sock"), os.path.join(sockdir, "d.txt")
    mbdyn = RecordedModalMbdyn(sock, rows, nloads)
    rc, out, _ = run_lammps(DECK.format(forces=forces, sock=sock, fem=FEM, type=type_, dump=dump, steps=steps),
                            sockdir, nprocs=nprocs, timeout=120)
    mbdyn.join(60)
    assert mbdyn.error is None, (mbdyn.error, error_line(out) or out[-3000:])
    assert rc == 0, out[-3000:]
    return rows, mbdyn, read_dump(dump)


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_type_modal_answers_the_recorded_generalized_forces(sockdir, nprocs):
    forces = "variable fy atom -100*y-vy/3\nvariable fz atom -50*z-vz/6\nfix law all addforce 0.0 v_fy v_fz"
    rows, mbdyn, _ = run_case(sockdir, "transcript_modal_type_modal.csv", "modal", 2, forces, nprocs)
    assert mbdyn.request == (7, 1, 2)  # MBC_MODAL, 2 modes, as the recording peer sent
    want = recorded_answers(rows)
    assert len(mbdyn.answers) == len(want) == 6
    worst = 0.0
    for (c, got), (wc, w) in zip(mbdyn.answers, want):
        assert c == wc == 6
        worst = max(worst, max(abs(g - e) for g, e in zip(got, w)))
    # the recorded p are about 6: a few ulps of the peer's -kq q - cq qdot, summed here over 3 atoms
    assert worst <= 1e-14, worst
    print(f"type modal: max |p - p_recorded| = {worst:.2e}")


@pytest.mark.parametrize("transcript,type_,nloads,messages", [
    ("transcript_loose.csv", "all", 8, 51), ("transcript_modal_type_rigid.csv", "rigid", 6, 6)])
def test_atoms_follow_the_recorded_modal_node_and_modes(sockdir, transcript, type_, nloads, messages):
    f3 = (0.3, -0.7, 1.1)
    forces = f"group a3 id 3\nfix push a3 addforce {f3[0]} {f3[1]} {f3[2]}"
    rows, mbdyn, frames = run_case(sockdir, transcript, type_, nloads, forces)
    assert mbdyn.request == (7, 5, 2)  # MBC_MODAL | MBC_REF_NODE, 2 modes (also with type rigid)
    kins = [v for d, c, v in rows if d == "mbdyn->peer" and c == 6]
    assert len(frames) == len(kins) == len(mbdyn.answers) == messages
    worst_x = worst_load = 0.0
    for kin, frame, (c, got) in zip(kins, frames, mbdyn.answers):
        xn, Rc, q = kin[0:3], kin[3:12], (kin[18:20] if type_ == "all" else (0.0, 0.0))
        R = [[Rc[0], Rc[3], Rc[6]], [Rc[1], Rc[4], Rc[7]], [Rc[2], Rc[5], Rc[8]]]
        for p in range(3):
            d = (0.5 * p, q[1] * W[p], q[0] * W[p])  # rest X + q1 Phi1 (z) + q2 Phi2 (y)
            x = [xn[a] + sum(R[a][b] * d[b] for b in range(3)) for a in range(3)]
            worst_x = max(worst_x, max(abs(x[a] - frame[p][a]) for a in range(3)))
        arm = [frame[2][a] - xn[a] for a in range(3)]
        M = (arm[1] * f3[2] - arm[2] * f3[1], arm[2] * f3[0] - arm[0] * f3[2], arm[0] * f3[1] - arm[1] * f3[0])
        local = [sum(R[b][a] * f3[b] for b in range(3)) for a in range(3)]
        expect = list(f3) + list(M) + ([W[2] * local[2], W[2] * local[1]] if type_ == "all" else [])
        assert c == 6
        worst_load = max(worst_load, max(abs(g - e) for g, e in zip(got, expect)))
    assert worst_x <= 1e-15, worst_x
    assert worst_load <= 1e-15, worst_load
    print(f"type {type_}: max position error {worst_x:.2e}, max load error {worst_load:.2e}")


K_SELF, GAMMA = 5.0, 0.7  # the tight deck's fix spring/self and fix viscous


def closed_form_loads(kin):
    """F, M, p of f_i = -K (x_i - X_i) - gamma v_i on the three atoms placed by the message kin
    (x_i = x_n + R (X_i + d_i), v_i = v_n + w x (x_i - x_n) + R d'_i, d_i = q1 Phi1 + q2 Phi2)."""
    xn, Rc, vn, w, q, qd = kin[0:3], kin[3:12], kin[12:15], kin[15:18], kin[18:20], kin[20:22]
    R = [[Rc[0], Rc[3], Rc[6]], [Rc[1], Rc[4], Rc[7]], [Rc[2], Rc[5], Rc[8]]]
    rot = lambda d: [sum(R[a][b] * d[b] for b in range(3)) for a in range(3)]  # noqa: E731
    F, M, p = [0.0] * 3, [0.0] * 3, [0.0, 0.0]
    for i in range(3):
        X = (0.5 * i, 0.0, 0.0)
        arm = rot((X[0], q[1] * W[i], q[0] * W[i]))
        x = [xn[a] + arm[a] for a in range(3)]
        dv = rot((0.0, qd[1] * W[i], qd[0] * W[i]))
        wx = (w[1] * arm[2] - w[2] * arm[1], w[2] * arm[0] - w[0] * arm[2], w[0] * arm[1] - w[1] * arm[0])
        v = [vn[a] + wx[a] + dv[a] for a in range(3)]
        f = [-K_SELF * (x[a] - X[a]) - GAMMA * v[a] for a in range(3)]
        m = (arm[1] * f[2] - arm[2] * f[1], arm[2] * f[0] - arm[0] * f[2], arm[0] * f[1] - arm[1] * f[0])
        local = [sum(R[b][a] * f[b] for b in range(3)) for a in range(3)]
        for a in range(3):
            F[a] += f[a]
            M[a] += m[a]
        p[0] += W[i] * local[2]
        p[1] += W[i] * local[1]
    return F + M + p


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_tight_answers_every_recorded_iterate(sockdir, nprocs):
    """type all, tight: MBDyn's step-1 prediction comes first (no start-up exchange in this
    model); every iterate is answered with the loads re-evaluated at its pose, 2 until two
    consecutive iterates differ by at most 1e-10 in every value (the recording peer's test), then 6."""
    forces = f"fix tether all spring/self {K_SELF}\nfix damp all viscous {GAMMA}"
    rows = read("transcript_tight.csv")
    steps = sum(1 for d, c, _ in rows if d == "peer->mbdyn" and c == 6)
    sock, dump = os.path.join(sockdir, "m.sock"), os.path.join(sockdir, "d.txt")
    mbdyn = RecordedModalMbdyn(sock, rows, 8)
    deck = DECK.format(forces=forces, sock=sock, fem=FEM, type="all", dump=dump, steps=steps).replace(
        "type all connect_timeout", "type all coupling tight tolerance 1e-10 max_iterations 15 startup_exchange no "
        "match 1e-3 connect_timeout")  # matched at step 1's predicted pose (T v0 = 2e-4 from t0's)
    rc, out, _ = run_lammps(deck, sockdir, nprocs=nprocs, timeout=120)
    mbdyn.join(60)
    assert mbdyn.error is None, (mbdyn.error, error_line(out) or out[-3000:])
    assert rc == 0, out[-3000:]
    assert mbdyn.request == (7, 5, 2)
    kins = [v for d, c, v in rows if d == "mbdyn->peer" and c == 2]
    want = recorded_answers(rows)
    assert len(mbdyn.answers) == len(kins) == len(want) == 194
    assert [c for c, _ in mbdyn.answers] == [c for c, _ in want]  # the recorded 2 / 6 sequence
    expect = [closed_form_loads(k) for k in kins]
    fields = [(0, 3), (3, 6), (6, 7), (7, 8)]  # F, M, p1, p2
    worst = 0.0
    for a, b in fields:
        scale = max(max(abs(v) for v in e[a:b]) for e in expect)
        dev = max(max(abs(g - e) for g, e in zip(got[a:b], e[a:b])) for (_, got), e in zip(mbdyn.answers, expect))
        worst = max(worst, dev / scale)

    # each iterate's own pose: loads one iterate late would be off by K and gamma times the
    # iterates' motion
    # (the largest change of a load between two iterates of one step, relative to its field)
    stale = max(max(abs(expect[j][c] - expect[j - 1][c]) for c in range(8)) / max(abs(v) for e in expect for v in e)
                for j in range(1, len(expect)) if want[j - 1][0] == 2)
    print(f"type all tight: {len(kins)} iterates, recorded command sequence; loads vs closed form "
          f"{worst:.2e} of each field's largest (loads one iterate late: up to {stale:.1e} of the largest load)")
    assert worst <= 1e-12, worst


BAD = """plugin load ${{plugin}}
units si
atom_style atomic
region box block -5 5 -5 5 -5 5
create_box 1 box
mass 1 1.0
create_atoms 1 single {x} 0 0 units box
fix M all mbdyn path {sock} modal {fem} {extra} connect_timeout 1
run 1
"""


@pytest.mark.parametrize("fem,x,extra,message", [
    ("missing.fem", 0.0, "", "FEM file '"),
    ("body.fem", 0.0, "modes 3", "mode 3 is not in FEM file"),
    ("body.fem", 0.0, "modes 2 list 2 2", "mode 2 listed twice"),
    ("body.fem", 0.0, "type both", "expected all, rigid or modal after type, got 'both'"),
    ("body.fem", 0.0, "origin 9", "no FEM node labelled '9'"),
    ("body.fem", 0.0, "coupling medium", "coupling: expected loose or tight, got 'medium'"),
    ("body.fem", 0.0, "tolerance 1e-10", "'tolerance' is for coupling tight"),
    ("body.fem", 0.0, "coupling tight max_iterations 0", "max_iterations: expected an integer >= 1, got '0'"),
    ("body.fem", 0.0, "coupling tight tolerance -1", "expected tolerance >= 0, got -1"),
    ("body.fem", 0.0, "coupling tight startup_exchange maybe", "startup_exchange: expected yes or no, got 'maybe'"),
    ("body.fem", 0.25, "type modal", "atom 1 at (0.25, 0, 0) is 0.25 from the nearest FEM node"),
    ("body.fem", 0.0, "modes 0", "expected modes >= 1, got 0"),
    ("body.fem", 0.0, "substeps 4", "unknown keyword 'substeps'"),  # one MBDyn step per LAMMPS step
    ("body.fem", 0.0, "mesh lid", "mesh ID 'lid' does not exist"),
])
def test_bad_input_names_what_was_expected(sockdir, fem, x, extra, message):
    sock = os.path.join(sockdir, "none.sock")
    rc, out, _ = run_lammps(BAD.format(sock=sock, fem=os.path.join(DATA, fem), x=x, extra=extra), sockdir)
    assert rc != 0
    assert message in error_line(out), out[-2000:]
