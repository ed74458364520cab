"""fix mbdyn ... modal FEM-FILE mesh MESH-ID coupling tight, type all: the plate of
test_mbdyn_modal_mesh (5 x 3 FEM nodes, two modes in z) carried by a moving, rotating modal node and
deformed by its modes, with four spheres held in space pressing on four of its faces. A scripted
MBDyn (this file's peer) sends per step iterates whose modal coordinates follow the generalized
forces answered (q = q_free + C p, a fixed-point iteration) and whose node pose converges
geometrically; fix mbdyn answers 2 until two consecutive iterates differ by at most `tolerance`
in every value, or max_iterations is reached, then 6.
The contact law is linear with no damping and no tangential force (hooke/stiffness, gamman =
gammat = 0), so the wall force of each sphere is a closed form of the iterate's kinematics:
vertices P_v = x_n + R (X_v + sum_m q_m Phi_m(v)), f = kn (r - |d|) n on the face under the sphere
(d its centre's distance to the face's plane, n the face normal), split to the face's corners
with the contact point's barycentric weights w_v; then
  F = sum f_wall,  M = sum_v (P_v - x_n) x f_v,  p_m = sum_v Phi_m(v) . (R^T f_v).
Checked at every iterate (a vertex off by e would change the loads by kn e, here 1e4 e N), and at
every step's end directly: the dumped vertices = P_v of the converged iterate, the spheres' forces
= minus the closed-form wall forces. 1 rank = 2 ranks to 1e-12."""
import math
import os
import socket
import struct
import threading

import pytest

from dembridge import plugin_path
from gran_deck import GRAN_HEAD
from test_fix_mbdyn import error_line, run_lammps, sockdir  # noqa: F401 (fixture)
from test_mbdyn_mapping_mesh import read_stl
from test_mbdyn_modal_mesh import CELLS, H, NX, NY, L, R as RADIUS, node, phi, write_fem, write_stl

pytestmark = pytest.mark.skipif(not os.path.exists(plugin_path()), reason="needs the plugin (build dembridgeplugin)")

KN, DT, STEPS = 1.0e4, 1e-3, 16
TOLERANCE, MAX_IT = 1e-9, 8
C = 2.5e-6  # the scripted body's modal compliance: q = q_free + C p
AXIS = [a / math.sqrt(0.3 ** 2 + 0.9 ** 2 + 0.3 ** 2) for a in (0.3, 0.9, 0.3)]
SPHERES = [((i + 2 / 3) * H, (j - 1 + 1 / 3) * H, RADIUS - 1e-3) for i, j in CELLS]  # 1 mm into the plate
NODES = [node(i, j) for j in range(NY) for i in range(NX)]  # FEM node order (write_fem)


def rotation(theta):
    """Rodrigues: rows of R for the rotation by theta about AXIS."""
    c, s, u = math.cos(theta), math.sin(theta), AXIS
    k = [[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]]
    return [[c * (a == b) + s * k[a][b] + (1 - c) * u[a] * u[b] for b in range(3)] for a in range(3)]


def iterate_kinematics(k, j, q):
    """The message of iterate j of step k (k = 0: t0, the rest pose): x, R (column-major), v, w, q, q'."""
    t, w = k * DT, 2 * math.pi / (10 * DT)
    e = 0.0 if k == 0 else 2e-5 * (0.5 if k % 4 == 0 else 0.08) ** j  # the pose's iterates converge
    s, cs = math.sin(w * t), w * math.cos(w * t)
    x = [1e-3 * s + e, 5e-4 * s - e, 2e-4 * s + 0.5 * e]
    theta = 1.5e-3 * s + e
    Rm = rotation(theta)
    v = [1e-3 * cs, 5e-4 * cs, 2e-4 * cs]
    om = [1.5e-3 * cs * u for u in AXIS]
    qd = [2e-4 * cs, -3e-4 * cs]
    return x + [Rm[a][b] for b in range(3) for a in range(3)] + v + om + list(q) + qd


def q_free(k):
    s = math.sin(2 * math.pi * k / 10)
    return [2e-4 * s, -3e-4 * s]


class ScriptedModalMbdyn(threading.Thread):
    """MBDyn's `external modal, type all` in tight coupling (the socket created here): per step,
    iterates until fix mbdyn answers 6; records every (message, answer)."""

    def __init__(self, path, steps):
        super().__init__(daemon=True)
        self.steps, self.exchanges, self.error, self.request = steps, [], None, None
        self.srv = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.srv.bind(path)
        self.srv.listen(1)
        self.srv.settimeout(60)
        self.start()

    def recv(self, n):
        buf = b""
        while len(buf) < n:
            chunk = self.conn.recv(n - len(buf))
            if not chunk:
                raise ConnectionError(f"fix mbdyn closed after {len(buf)} of {n} bytes")
            buf += chunk
        return buf

    def exchange(self, kin):
        self.conn.sendall(b"\x02" + struct.pack(f"={len(kin)}d", *kin))
        c = self.recv(1)[0]
        loads = list(struct.unpack("=8d", self.recv(64)))
        self.exchanges.append((kin, c, loads))
        return c, loads

    def run(self):
        try:
            self.conn, _ = self.srv.accept()
            self.srv.close()
            self.conn.settimeout(60)
            self.request = struct.unpack("=BII", self.recv(9))
            self.conn.sendall(b"\x08")
            _, p = self.exchange(iterate_kinematics(0, 0, [0.0, 0.0]))  # t0, answered 6 at the set-up
            for k in range(1, self.steps + 1):
                for j in range(100):
                    q = [q_free(k)[m] + C * p[6 + m] for m in range(2)]
                    c, p = self.exchange(iterate_kinematics(k, j, q))
                    if c == 6:
                        break
            try:
                self.conn.sendall(b"\x05")
            except OSError:  # LAMMPS may have closed after its last answer
                pass
            self.conn.close()
        except Exception as e:  # reported by the test
            self.error = repr(e)


def deck(sock, d, procs=""):
    spheres = "\n".join(f"create_atoms 1 single {x!r} {y!r} {z!r} units box" for x, y, z in SPHERES)
    return f"""{GRAN_HEAD}
{procs}
region box block -0.1 0.5 -0.2 0.2 -0.2 0.2 units box
create_box 1 box
{spheres}
set type 1 diameter {2 * RADIUS}
set type 1 density 10000
fix m1 all property/global kn peratomtypepair 1 {KN}
fix m2 all property/global kt peratomtypepair 1 {KN}
fix m3 all property/global gamman peratomtypepair 1 0.0
fix m4 all property/global gammat peratomtypepair 1 0.0
fix m5 all property/global coefficientFriction peratomtypepair 1 0.4
pair_style gran model hooke/stiffness tangential no_history
pair_coeff * *
neighbor 0.005 bin
timestep {DT}
fix plate all mesh/surface/stress file {d}/plate.stl type 1
fix walls all wall/gran model hooke/stiffness tangential no_history mesh n_meshes 1 meshes plate
fix M all mbdyn path {sock} modal {d}/plate.fem modes 2 type all mesh plate coupling tight tolerance {TOLERANCE} &
  max_iterations {MAX_IT} connect_timeout 60 io_timeout 60
fix D all mesh/dump 1 stl {d}/mesh*.stl plate
dump A all custom 1 {d}/atoms.*.dump id x y z fx fy fz
dump_modify A format float %.17g sort id
run {STEPS}
"""


def sub(a, b):
    return [a[c] - b[c] for c in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[c] * b[c] for c in range(3))


def vertices(kin):
    """P_v of every FEM node for one message."""
    xn, Rc, q = kin[0:3], kin[3:12], kin[18:20]
    out = []
    for X in NODES:
        d = [X[0], X[1], X[2] + q[0] * phi(0, X[0]) + q[1] * phi(1, X[0])]
        out.append([xn[a] + sum(Rc[3 * b + a] * d[b] for b in range(3)) for a in range(3)])
    return out


def closed_form(kin):
    """(F, M, p) and each sphere's force from the wall, for the mesh placed by kin."""
    xn, Rc = kin[0:3], kin[3:12]
    P = vertices(kin)
    F, M, p, on_spheres = [0.0] * 3, [0.0] * 3, [0.0, 0.0], []
    for (i, j), centre in zip(CELLS, SPHERES):
        corners = [j * NX + i, j * NX + i + 1, (j + 1) * NX + i + 1]  # triangle (a, b, c) of write_stl's cell
        A, B, Cc = (P[v] for v in corners)
        n = cross(sub(B, A), sub(Cc, A))
        n = [x / math.sqrt(dot(n, n)) for x in n]
        dist = dot(sub(centre, A), n)
        cp = [centre[c] - dist * n[c] for c in range(3)]
        f_sphere = [KN * (RADIUS - abs(dist)) * math.copysign(1.0, dist) * n[c] for c in range(3)]
        on_spheres.append(f_sphere)
        area = dot(cross(sub(B, A), sub(Cc, A)), n)
        w = [dot(cross(sub(B, cp), sub(Cc, cp)), n) / area, dot(cross(sub(Cc, cp), sub(A, cp)), n) / area]
        w.append(1.0 - w[0] - w[1])
        for v, wv in zip(corners, w):
            fv = [-wv * f_sphere[c] for c in range(3)]
            arm = sub(P[v], xn)
            F = [F[c] + fv[c] for c in range(3)]
            M = [M[c] + m for c, m in enumerate(cross(arm, fv))]
            local = [sum(Rc[3 * a + b] * fv[b] for b in range(3)) for a in range(3)]  # R^T f
            for m in range(2):
                p[m] += phi(m, NODES[v][0]) * local[2]
    return F + M + p, on_spheres


def expected_commands(exchanges):
    """fix mbdyn's rule: 6 at the t0 exchange; in a step, 6 when two consecutive iterates differ by at
    most the tolerance in every value or at the max_iterations-th exchange, else 2."""
    out, j, before = [], 0, None
    for n, (kin, c, _) in enumerate(exchanges):
        if n == 0:
            out.append(6)
            continue
        change = max(abs(a - b) for a, b in zip(kin, before)) if j > 0 else math.inf
        done = j + 1 >= MAX_IT or change <= TOLERANCE
        out.append(6 if done else 2)
        before, j = kin, (0 if c == 6 else j + 1)
    return out


RUNS = {}


def coupled(d, nprocs):
    if nprocs in RUNS:
        return RUNS[nprocs]
    d = os.path.join(d, str(nprocs))
    os.makedirs(d)
    write_fem(f"{d}/plate.fem")
    write_stl(f"{d}/plate.stl")
    sock = f"{d}/m.sock"
    mbdyn = ScriptedModalMbdyn(sock, STEPS)
    rc, out, secs = run_lammps(deck(sock, d, "processors 2 1 1" if nprocs == 2 else ""), d, nprocs=nprocs,
                               timeout=120)
    mbdyn.join(60)
    assert mbdyn.error is None, (mbdyn.error, error_line(out) or out[-3000:])
    assert rc == 0, out[-3000:]
    RUNS[nprocs] = (d, mbdyn, secs)
    return RUNS[nprocs]


def test_tight_mesh_every_iterate_against_the_closed_form(sockdir):  # noqa: F811
    d, mbdyn, secs = coupled(sockdir, 1)
    ex = mbdyn.exchanges
    assert mbdyn.request == (7, 5, 2)  # MBC_MODAL | MBC_REF_NODE, 2 modes
    commands = [c for _, c, _ in ex]
    assert commands == expected_commands(ex)
    per_step = [len(s) + 1 for s in "".join(map(str, commands[1:])).split("6")[:-1]]
    assert len(per_step) == STEPS and MAX_IT in per_step and min(per_step) < MAX_IT  # both rules answer 6
    expect = [closed_form(kin)[0] for kin, _, _ in ex]
    worst = 0.0
    for a, b in ((0, 3), (3, 6), (6, 7), (7, 8)):  # F, M, p1, p2: relative to each field's largest value
        scale = max(abs(v) for e in expect for v in e[a:b])
        dev = max(abs(g - e) for (_, _, got), e in zip(ex, expect) for g, e in zip(got[a:b], e[a:b]))
        worst = max(worst, dev / scale)
    # what the test resolves: loads one iterate late would be off by this much (relative to the largest load)
    top = max(abs(v) for e in expect for v in e)
    stale = max(max(abs(a - b) for a, b in zip(expect[n], expect[n - 1])) for n in range(2, len(ex))
                if commands[n - 1] == 2) / top
    # each step's end: the mesh (fix mesh/dump) and the spheres' forces at the converged iterate
    final = [kin for kin, c, _ in ex if c == 6]
    worst_x = worst_f = fscale = 0.0
    for k, kin in enumerate(final):
        P = vertices(kin)
        for tri in read_stl(f"{d}/mesh{k}.stl"):
            for v in tri:
                X = min(P, key=lambda x: sum((x[c] - v[c]) ** 2 for c in range(3)))
                worst_x = max(worst_x, max(abs(v[c] - X[c]) for c in range(3)))
        rows = [l.split() for l in open(f"{d}/atoms.{k}.dump").read().split("fx fy fz\n")[1].splitlines()]
        for row, f in zip(rows, closed_form(kin)[1]):
            fscale = max(fscale, max(map(abs, f)))
            worst_f = max(worst_f, max(abs(float(row[4 + c]) - f[c]) for c in range(3)))
    theta = max(abs(math.acos(min(1.0, (kin[3] + kin[7] + kin[11] - 1) / 2))) for kin in final)
    print(f"modal mesh tight: {len(ex)} exchanges in {secs:.1f} s, iterates per step {per_step}; loads vs closed form "
          f"{worst:.1e} of each field's largest (one iterate late: {stale:.1e}); converged vertices {worst_x:.1e} m, sphere forces "
          f"{worst_f / fscale:.1e} of {fscale:.3g} N; node rotation up to {theta:.1e} rad")
    assert worst <= 1e-12 and stale > 1e-6
    assert worst_x <= 1e-15
    assert worst_f <= 1e-12 * fscale


@pytest.mark.two_cores
def test_tight_mesh_two_ranks_answer_as_one(sockdir):  # noqa: F811
    one = coupled(sockdir, 1)[1].exchanges
    two = coupled(sockdir, 2)[1].exchanges
    assert [c for _, c, _ in two] == [c for _, c, _ in one]
    scale = max(abs(v) for _, _, l in one for v in l)
    worst = max(abs(a - b) for (_, _, la), (_, _, lb) in zip(one, two) for a, b in zip(la, lb))
    print(f"modal mesh tight: 2 ranks vs 1 rank {worst / scale:.1e} of the largest load {scale:.3g} "
          f"({len(two)} answers)")
    assert worst <= 1e-12 * scale
