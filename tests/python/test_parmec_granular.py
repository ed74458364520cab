"""Parmec GRANULAR contact and OBSTACLE (issue 13 deliverable 3; fix parmec/granular, doc/fix_parmec_granular.md,
doc/parmec_front_end.md) through the Parmec front end: closed forms (restitution of the damper ratio on a static
obstacle and between two spheres with momentum conserved, friction-limited sliding mu*g, rolling 5/7), an
independent replay of Parmec's leap-frog for the drop, a moving obstacle, 1 vs 2 ranks, restart, bad input."""
import math

import pytest

from dembridge import new_lammps
from dembridge.parmec import ParmecError, run_script
from parmec_contact_runs import atoms_by_id, fix_error, histories_on_ranks

PLANE = "[(-L, -L, 0, L, -L, 0, L, L, 0), (-L, -L, 0, L, L, 0, -L, L, 0)]"  # z = 0, two triangles


def run(tmp_path, body, argv=()):
    script = tmp_path / "model.py"
    script.write_text("import math\n" + body)
    return run_script(str(script), list(argv), workdir=str(tmp_path / "wd"))


def restitution(z):
    return math.exp(-math.pi * z / math.sqrt(1 - z * z))


DROP = """
m = MATERIAL(1000.0, 1e9, 0.25)
r, L, k, z = 0.1, 1.0, 1e6, 0.2
p = SPHERE((0.0, 0.0, r + 0.01), r, m, 1)
VELOCITY(p, (0.0, 0.0, -1.0))
OBSTACLE(""" + PLANE + """, 2)
GRANULAR(1, 2, k, z)
M = 1000.0 * 4.0 / 3.0 * math.pi * r ** 3
T = math.pi / math.sqrt(k / M * (1 - z * z))
h = T / float(ARGV()[0])
PZ, VZ = HISTORY('PZ', p), HISTORY('VZ', p)
DEM(0.03, h)
"""


def drop_replay(h, steps, r=0.1, k=1e6, z=0.2):
    """Parmec's recurrence for the drop (spec §1.1, §11): forces at x_{n+1/2} and v_n, the unforced half
    drift first; contact while the overlap r - x > 0 with the plane, m_eff = m."""
    M = 1000.0 * 4.0 / 3.0 * math.pi * r ** 3
    en = z * 2.0 * math.sqrt(k * M)
    x, v = r + 0.01 + 0.5 * h * -1.0, -1.0
    for _ in range(steps):
        d = r - x
        f = k * d + en * -v if d > 0 else 0.0  # vij . n = (0 - v) along +z
        v += h * f / M
        x += h * v
    return x, v


def test_drop_on_static_obstacle_bounces_with_the_damper_restitution(tmp_path):
    """A sphere dropped (no gravity) on a two-triangle obstacle plane: the rebound velocity is
    exp(-pi z / sqrt(1 - z^2)) to O(h) (halving h halves the error), and equals the replay of Parmec's
    recurrence to 1e-12 relative (the flat surface acts once, not once per triangle)."""
    errs = []
    for div in (100, 200):
        ns = run(tmp_path, DROP, [str(div)])
        e = ns["VZ"][-1] / 1.0
        errs.append(abs(e - restitution(0.2)))
        steps = len(ns["VZ"])  # row n (n >= 1) holds the results of step n; steps 0 ... n
        x, v = drop_replay(ns["h"], steps)
        assert abs(ns["VZ"][-1] - v) <= 1e-12 * abs(v), (ns["VZ"][-1], v)
        assert abs(ns["PZ"][-1] - x) <= 1e-12 * abs(x), (ns["PZ"][-1], x)
    assert errs[1] < 0.01 * restitution(0.2)
    assert errs[1] < 0.6 * errs[0], errs  # O(h)


def drop_replay_parmec(h, steps, r=0.1, k=1e6, z=0.2, contacts=2):
    """Parmec's own drop on the shared edge of the two triangles: one contact per triangle (each with the full
    k and e_n), and in the step that finds the sphere separated each contact acts once more with its negative
    depth before it is dropped (forces.ispc returns 'gone' after computing the force)."""
    M = 1000.0 * 4.0 / 3.0 * math.pi * r ** 3
    en = z * 2.0 * math.sqrt(k * M)
    x, v, touching = r + 0.01 + 0.5 * h * -1.0, -1.0, False
    for _ in range(steps):
        d = r - x
        f = 0.0
        if d > 0 or touching:
            f = contacts * (k * d + en * -v)
        touching = d > 0
        v += h * f / M
        x += h * v
    return x, v


def test_parmec_quirks_drop_on_a_shared_edge_counts_both_triangles(tmp_path):
    """--parmec-quirks: the sphere lands on the diagonal shared by the two triangles, and Parmec makes a contact
    with each (twice the stiffness and damping) plus a last tensile force at separation: the replay of that
    recurrence matches to 1e-12; the default counts the flat surface once (previous test)."""
    script = tmp_path / "model.py"
    script.write_text("import math\n" + DROP)
    ns = run_script(str(script), ["200"], quirks=True, workdir=str(tmp_path / "wdq"))
    x, v = drop_replay_parmec(ns["h"], len(ns["VZ"]))
    assert abs(ns["VZ"][-1] - v) <= 1e-12 * abs(v), (ns["VZ"][-1], v)
    assert abs(ns["PZ"][-1] - x) <= 1e-12 * abs(x), (ns["PZ"][-1], x)
    x1, v1 = drop_replay(ns["h"], len(ns["VZ"]))
    assert abs(v - v1) > 0.05  # the two semantics differ visibly


SLIDE = """
m = MATERIAL(1000.0, 1e9, 0.25)
r, L, k, mu, g = 0.1, 5.0, 1e7, 0.3, 10.0
M = 1000.0 * 4.0 / 3.0 * math.pi * r ** 3
p = SPHERE((0.0, 0.0, r - M * g / k), r, m, 1)   # resting overlap
VELOCITY(p, (1.0, 0.0, 0.0))
OBSTACLE(""" + PLANE + """, 2)
GRANULAR(1, 2, k, 1.0, mu)
GRAVITY(0.0, 0.0, -g)
if ARGV()[0] == 'slide':
    RESTRAIN(p, angular=[1, 0, 0, 0, 1, 0, 0, 0, 1])
VX = HISTORY('VX', p)
t = HISTORY('TIME')
DEM(float(ARGV()[1]), 2e-5)
"""


def test_friction_limited_sliding_decelerates_at_mu_g(tmp_path):
    """A sphere sliding on a static obstacle without rotation (RESTRAINed spin) decelerates at mu g."""
    ns = run(tmp_path, SLIDE, ["slide", "0.2"])
    t, vx = ns["t"], ns["VX"]
    i1, i2 = len(t) // 4, 3 * len(t) // 4
    decel = (vx[i1] - vx[i2]) / (t[i2] - t[i1])
    assert abs(decel - 0.3 * 10.0) < 0.005 * 3.0, decel
    assert abs(vx[-1] - (1.0 - 3.0 * t[-1])) < 0.01, vx[-1]


def test_free_sphere_keeps_decelerating_under_parmecs_unrescaled_spring(tmp_path):
    """Without the restraint friction spins the sphere up (torque r mu m g), but Parmec's tangential spring is
    not rescaled at the Coulomb limit: it holds all the slip, so the force stays mu_d F_n along it after the
    contact point's slip reverses (t > 2 v0 / (7 mu g) = 0.095 s) and the sphere never settles into rolling
    at 5/7 v0: v = v0 - mu g t, omega = 5 mu g t / (2 r), as long as the spring has not unloaded."""
    ns = run(tmp_path, SLIDE.replace("VX = HISTORY('VX', p)", "VX, OY = HISTORY('VX', p), HISTORY('OY', p)"),
             ["roll", "0.15"])
    t = ns["t"][-1]
    assert abs(ns["VX"][-1] - (1.0 - 3.0 * t)) < 0.005, ns["VX"][-1]
    assert abs(ns["OY"][-1] - 5.0 * 3.0 * t / (2.0 * 0.1)) < 0.01 * 22.5, ns["OY"][-1]


HEAD_ON = """
m = MATERIAL(1000.0, 1e9, 0.25)
k, z = 1e6, float(ARGV()[0])
a = SPHERE((0.0, 0.0, 0.0), 0.1, m, 1)
b = SPHERE((0.3, 0.0, 0.0), 0.15, m, 2)
VELOCITY(a, (1.0, 0.0, 0.0))
VELOCITY(b, (-0.5, 0.0, 0.0))
GRANULAR(1, 2, k, z)
ma = 1000.0 * 4.0 / 3.0 * math.pi * 0.1 ** 3
mb = 1000.0 * 4.0 / 3.0 * math.pi * 0.15 ** 3
VA, VB = HISTORY('VX', a), HISTORY('VX', b)
XA, XB = HISTORY('PX', a), HISTORY('PX', b)
DEM(0.1, 2e-6)
"""


@pytest.mark.parametrize("z", [0.0, 0.1, 0.3])
def test_two_spheres_head_on_conserve_momentum_with_the_expected_restitution(tmp_path, z):
    ns = run(tmp_path, HEAD_ON, [str(z)])
    ma, mb = ns["ma"], ns["mb"]
    p0 = ma * 1.0 + mb * -0.5
    for va, vb in zip(ns["VA"], ns["VB"]):
        assert abs(ma * va + mb * vb - p0) <= 1e-12 * abs(p0)
    e = (ns["VB"][-1] - ns["VA"][-1]) / 1.5
    assert abs(e - restitution(z)) < 0.005, (e, restitution(z))


def head_on_replay(h, steps, z, quirks=False, k=1e6):
    """Parmec's recurrence for the head-on pair along x (spec §1.1, §11): n = (x_a - x_b)/|x_a - x_b| for a,
    v_ab = v_b - v_a, F_n = k d + e_n (v_ab . n) on a along n, the opposite on b; m_eff = 1/(1/m_a + 1/m_b)."""
    ma = 1000.0 * 4.0 / 3.0 * math.pi * 0.1 ** 3
    mb = 1000.0 * 4.0 / 3.0 * math.pi * 0.15 ** 3
    en = z * 2.0 * math.sqrt(k * (1.0 / (1.0 / ma + 1.0 / mb)))
    xa, xb, va, vb = 0.0 + 0.5 * h * 1.0, 0.3 + 0.5 * h * -0.5, 1.0, -0.5
    touching = False
    for _ in range(steps):
        d = 0.25 - (xb - xa)
        fn = 0.0
        if d > 0 or (quirks and touching):
            fn = k * d + en * -(vb - va)  # n = -1 for a
        touching = d > 0
        va += h * -fn / ma
        vb += h * fn / mb
        xa += h * va
        xb += h * vb
    return xa, xb, va, vb


@pytest.mark.parametrize("quirks", [False, True])
def test_two_spheres_head_on_equal_parmecs_recurrence(tmp_path, quirks):
    """The head-on pair (z = 0.3) against the replay of Parmec's recurrence: positions and velocities of both
    spheres to 1e-12 (quirks: the last tensile force at separation included)."""
    script = tmp_path / "model.py"
    script.write_text("import math\n" + HEAD_ON.replace("DEM(0.1, 2e-6)", "DEM(0.045, 2e-6)"))  # contact 0.033-0.037 s
    ns = run_script(str(script), ["0.3"], quirks=quirks, workdir=str(tmp_path / "wd"))
    xa, xb, va, vb = head_on_replay(2e-6, len(ns["VA"]), 0.3, quirks)
    assert abs(ns["VA"][-1] - va) <= 1e-12 and abs(ns["VB"][-1] - vb) <= 1e-12, (ns["VA"][-1], va, ns["VB"][-1], vb)
    assert abs(ns["XA"][-1] - xa) <= 1e-12 and abs(ns["XB"][-1] - xb) <= 1e-12, (ns["XA"][-1], xa, ns["XB"][-1], xb)
    assert vb - va > 0.5  # they collided and separate (e = 0.37 of the approach speed 1.5)
    other = head_on_replay(2e-6, len(ns["VA"]), 0.3, not quirks)
    assert abs(other[2] - va) > 1e-6  # the last tensile force is visible


MOVING = """
m = MATERIAL(1000.0, 1e9, 0.25)
r, L, k = 0.05, 1.0, 1e6
n = int(ARGV()[0]) if ARGV() else 4
P = []
slide = len(ARGV()) > 1
for i in range(n):
    for j in range(n):
        for l in range(2):
            P.append(SPHERE((-0.3 + 0.2 * i + 0.01 * l, -0.3 + 0.2 * j, 0.06 + 0.11 * l), r, m, 1 + l))
            if slide:  # across the middle of the box, where 2 ranks split it
                VELOCITY(P[-1], (3.0, 0.0, 0.0))
# a plate translating up and down and spinning slowly about z through its centre
OBSTACLE(""" + PLANE + """, 3, point=(0.0, 0.0, 0.0), linear=lambda t: (0.0, 0.0, 0.2 * math.cos(30.0 * t)),
         angular=lambda t: (0.0, 0.0, 0.5))
GRANULAR(1, 3, k, 0.3, 0.4)
GRANULAR(2, 3, k, 0.5, (0.5, 0.3), kskn=0.3)
GRANULAR(0, 0, k, 0.2, 0.2)
GRAVITY(0.0, 0.0, -10.0)
H = {c: [HISTORY(c, q) for q in P] for c in ('PX', 'PY', 'PZ')}
DEM(0.1, 2e-5, 0.01)
"""


def test_moving_obstacle_lifts_and_turns_the_spheres(tmp_path):
    """The plate rises (v = 0.2 cos 30t) and spins at 0.5 rad/s about z: the spheres resting on it follow it up
    and friction carries them round (a turn of at most 0.5 x 0.1 = 0.05 rad); the top layer (colour 2) rests
    on the bottom one (pairing (0, 0))."""
    ns = run(tmp_path, MOVING, ["3"])
    H = ns["H"]
    rise = 0.2 / 30.0 * math.sin(30.0 * 0.1)  # plate displacement at t = 0.1
    bottom = [z[-1] for k, z in enumerate(H["PZ"]) if k % 2 == 0]
    assert all(abs(z - (0.05 + rise)) < 0.01 for z in bottom), (bottom, rise)
    top = [z[-1] for k, z in enumerate(H["PZ"]) if k % 2 == 1]
    assert all(t > b + 0.05 for t, b in zip(top, bottom))
    for k in range(0, len(H["PX"]), 2):
        x0, y0, x1, y1 = H["PX"][k][0], H["PY"][k][0], H["PX"][k][-1], H["PY"][k][-1]
        if math.hypot(x0, y0) > 0.1:
            turn = math.atan2(x0 * y1 - y0 * x1, x0 * x1 + y0 * y1)
            assert 0.01 < turn <= 0.05 + 1e-3, (k, turn)


LIFT = """
m = MATERIAL(1000.0, 1e9, 0.25)
r, L, k = 0.1, 1.0, 1e6
p = SPHERE((0.0, 0.0, r), r, m, 1)
up, still = TSERIES(0.5), TSERIES(0.0)
if ARGV()[0] == 'callback':
    OBSTACLE(""" + PLANE + """, 2, point=(0, 0, 0), linear=lambda t: (0, 0, 0.5))
else:
    OBSTACLE(""" + PLANE + """, 2, point=(0, 0, 0), linear=(still, still, up))
GRANULAR(1, 2, k, 1.0)
GRAVITY(0.0, 0.0, -10.0)
PZ = HISTORY('PZ', p)
DEM(0.1, 1e-5)
DEM(0.1, 1e-5)
M = 1000.0 * 4.0 / 3.0 * math.pi * r ** 3
"""


def test_obstacle_motion_by_callback_or_tseries_over_two_dem_calls(tmp_path):
    """A plate rising at 0.5 m/s for two DEM calls of 0.1 s (the callback re-tabulated for the second call)
    carries a resting sphere up by 0.1 m, with the same result from a callback and from TSERIES numbers."""
    got = {}
    for how in ("callback", "tseries"):
        ns = run(tmp_path, LIFT, [how])
        got[how] = ns["PZ"][-1]
        sag = ns["M"] * 10.0 / 1e6  # static overlap m g / k
        assert abs(got[how] - (0.1 + 0.1 - sag)) < 2e-5, got[how]
    assert got["callback"] == got["tseries"]


@pytest.mark.two_cores
def test_one_and_two_ranks_agree(tmp_path):
    """The moving-obstacle pile on 1 and 2 MPI ranks, the spheres sliding at 3 m/s across the rank boundary
    (their contact springs migrate with them): every HISTORY value within 1e-12 (relative)."""
    out = histories_on_ranks(tmp_path, MOVING, ["4", "slide"])
    worst = 0.0
    for key in out[1]:
        for a, b in zip(out[1][key], out[2][key]):
            for u, w in zip(a, b):
                worst = max(worst, abs(u - w) / max(1.0, abs(u)))
    assert worst <= 1e-12, worst


# ------------------------------------------------------------------------------------------ LAMMPS level

def deck(lmp, extra=""):
    for c in ["units si", "atom_style sphere", "atom_modify map array", "boundary m m m", "comm_modify vel yes",
              "region b block -1 1 -1 1 -0.5 1", "create_box 2 b",
              "create_atoms 1 single -0.2 0 0.0499", "create_atoms 2 single 0.0 0.1 0.2",
              "create_atoms 1 single 0.15 -0.1 0.0499", "create_atoms 2 single 0.2 0.2 0.3",
              "set group all diameter 0.1", "set group all density 1000", "velocity all set 0.1 0 -0.1",
              "pair_style zero 0.1", "pair_coeff * *", "neighbor 0.01 bin", "neigh_modify delay 0 every 1 check yes",
              "timestep 2e-5",
              "fix G all parmec/granular tseries VZ 0 0.2 0.05 -0.2 0.1 0.2 "
              "pairing 1 3 spring 1e6 damper 1.0 friction 0.4 pairing 0 0 spring 1e6 damper 0.5 friction 0.5 0.3 "
              "obstacle 1 2 -1 -1 0 1 -1 0 1 1 0 -1 -1 0 1 1 0 -1 1 0 color 3 point 0 0 0 linear 0 0 VZ angular 0 0 0.5 "
              + extra,
              "fix F all gravity 10 vector 0 0 -1", "fix I all nve/sphere"]:
        lmp.command(c)


def test_restart_of_a_moving_obstacle_continues_bitwise(tmp_path):
    """write_restart at step 1500 of 3000, read back with the same fix definitions: the obstacle pose, the Parmec
    clock and every contact's tangential spring continue; positions equal the split run (1500 + 1500 steps in one
    process, the same setup pass between the runs) bitwise."""
    a = new_lammps()
    deck(a)
    a.command("run 1500")
    a.command("run 1500")
    ref = atoms_by_id(a, "x")
    assert a.extract_fix("G", 0, 1, 1) > 0  # obstacle contacts at the end
    a.close()
    b = new_lammps()
    deck(b)
    b.command("run 1500")
    b.command(f"write_restart {tmp_path / 'r.bin'}")
    b.close()
    c = new_lammps()
    c.command(f"read_restart {tmp_path / 'r.bin'}")
    for cmd in ["comm_modify vel yes", "pair_style zero 0.1", "pair_coeff * *", "neighbor 0.01 bin",
                "neigh_modify delay 0 every 1 check yes", "timestep 2e-5",
                "fix G all parmec/granular tseries VZ 0 0.2 0.05 -0.2 0.1 0.2 "
                "pairing 1 3 spring 1e6 damper 1.0 friction 0.4 pairing 0 0 spring 1e6 damper 0.5 friction 0.5 0.3 "
                "obstacle 1 2 -1 -1 0 1 -1 0 1 1 0 -1 -1 0 1 1 0 -1 1 0 color 3 point 0 0 0 linear 0 0 VZ angular 0 0 0.5",
                "fix F all gravity 10 vector 0 0 -1", "fix I all nve/sphere", "run 1500"]:
        c.command(cmd)
    got = atoms_by_id(c, "x")
    c.close()
    assert (got == ref).all(), abs(got - ref).max()


LAMMPS_BAD = [
    ("pairing 1 2 spring -1", "spring must be >= 0"),
    ("pairing 0 2 spring 1", "colour 0 only as (0, 0)"),
    ("pairing 1 2 damper 1", "expected 'spring K'"),
    ("obstacle 7 1 0 0 0 1 0 0 2 0 0 color 1", "obstacle 7"),
    ("obstacle 7 1 0 0 0 1 0 0 0 1 0 color 0", "must be a positive integer"),
    ("obstacle 7 1 0 0 0 1 0 0 0 1 0 color 1 linear 1 0 0", "needs its reference 'point x y z'"),
    ("obstacle 7 1 0 0 0 1 0 0 0 1 0 color 1 point 0 0 0 linear V 0 0", "TSERIES ID 'V' is not defined"),
    ("bogus 3", "unknown keyword 'bogus'"),
    ("color q_x", "color: expected 'type' or i_NAME"),
]


@pytest.mark.parametrize("defs,message", LAMMPS_BAD, ids=[f"lmp_bad{i}" for i in range(len(LAMMPS_BAD))])
def test_lammps_bad_input(defs, message):
    err = fix_error(defs)
    assert message in err, err


def test_lammps_needs_a_pair_cutoff_covering_the_spheres():
    lmp = new_lammps()
    for c in ["units si", "atom_style sphere", "region b block -1 1 -1 1 -1 1", "create_box 1 b",
              "create_atoms 1 single 0 0 0", "set group all diameter 0.2", "pair_style zero 0.1", "pair_coeff * *",
              "comm_modify vel yes", "fix G all parmec/granular pairing 1 1 spring 1e5", "fix I all nve/sphere"]:
        lmp.command(c)
    with pytest.raises(Exception) as e:
        lmp.command("run 1")
    assert "pair cutoff (0.1) is below twice the largest radius (0.1)" in str(e.value), str(e.value)
    lmp.close()


# ------------------------------------------------------------------------------------------ front end bad input

PRE = "m = MATERIAL(1000.0, 1e9, 0.25)\np = SPHERE((0, 0, 0), 0.1, m, 1)\nT = (0, 0, 0, 1, 0, 0, 0, 1, 0)\n"
MESH_CUBE = ("MESH([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1], "
             "[8, 0, 1, 2, 3, 4, 5, 6, 7, m], m, 1)\n")
BAD = [
    ("GRANULAR(0, 5, 1e5)", "GRANULAR: arguments 'color1', 'color2' = (0, 5): colour 0 only as (0, 0)"),
    ("GRANULAR(-1, 2, 1e5)", "GRANULAR: argument 'color1' must be an integer >= 0"),
    ("GRANULAR(1, 'blue', 1e5)", "GRANULAR: argument 'color2'"),
    ("GRANULAR(1, 2, -1.0)", "GRANULAR: argument 'spring' must be a number >= 0"),
    ("GRANULAR(1, 2, 1e5, damper=-0.5)", "GRANULAR: argument 'damper'"),
    ("GRANULAR(1, 2, 1e5, friction=(0.1,))", "GRANULAR: argument 'friction' must be a number or a tuple"),
    ("GRANULAR(1, 2, 1e5, friction=(0.1, -0.2))", "GRANULAR: argument 'friction' must be >= 0"),
    ("GRANULAR(1, 2, 1e5, kskn=-1.0)", "GRANULAR: argument 'kskn'"),
    ("GRANULAR(1, 2, 1e5, rolling=0.1)", "GRANULAR: argument 'rolling' = 0.1 is not supported"),
    ("GRANULAR(1, 2, 1e5, drilling=0.1)", "GRANULAR: argument 'drilling' = 0.1 is not supported"),
    ("GRANULAR(1, 2, 1e5, spin=0.1)", "spin"),
    ("OBSTACLE([(0, 0, 0, 1, 0, 0, 0, 1)], 1)", "OBSTACLE: argument 'triangles': triangle 0 must be a tuple of 9"),
    ("OBSTACLE([], 1)", "OBSTACLE: argument 'triangles' must be a non-empty list"),
    ("OBSTACLE([(0, 0, 0, 1, 0, 0, 2, 0, 0)], 1)", "OBSTACLE: argument 'triangles': triangle 0 is degenerate"),
    ("OBSTACLE([T], 0)", "OBSTACLE: argument 'color' must be a positive integer"),
    ("OBSTACLE([T, T], [1])", "OBSTACLE: argument 'color': expected one colour per triangle (2), got 1"),
    ("OBSTACLE([T], 1, linear=lambda t: (0, 0, 1))", "OBSTACLE: argument 'point' is required"),
    ("OBSTACLE([T], 1, point=(0, 0), linear=lambda t: (0, 0, 1))", "OBSTACLE: argument 'point'"),
    ("OBSTACLE([T], 1, point=(0, 0, 0), linear=(0, 0))", "OBSTACLE: argument 'linear'"),
    ("OBSTACLE([T], 1, point=(0, 0, 0), linear=lambda t: (0, 1))\nGRANULAR(1, 1, 1e5)\nDEM(0.001, 1e-4)",
     "OBSTACLE 0: argument 'linear': the callback (lambda at line"),
    (MESH_CUBE + MESH_CUBE + "GRANULAR(1, 1, 1e5)\nDEM(0.001, 1e-4)",
     "DEM: MESH particles 1 and 2: the GRANULAR pairing of their colours (1, 1) has spring > 0"),
    ("GRANULAR(0, 0, 1e5)\n" + MESH_CUBE + MESH_CUBE + "DEM(0.001, 1e-4)",
     "DEM: MESH particles 1 and 2: the GRANULAR pairing of their colours (1, 1) has spring > 0"),
    ("DEM(0.001, 1e-4)\nGRANULAR(1, 1, 1e5)", "GRANULAR: changing the model after the first DEM"),
]


@pytest.mark.parametrize("body,message", BAD, ids=[f"bad{i:02d}" for i in range(len(BAD))])
def test_front_end_bad_input(tmp_path, body, message):
    with pytest.raises((ParmecError, TypeError)) as e:
        run(tmp_path, PRE + body + "\n")
    assert message in str(e.value), str(e.value)


BOUNCE = """
# the shape of Parmec's examples/bounce.py: a default pairing, an obstacle, step = ratio * CRITICAL()
mat = MATERIAL(1000.0, 1e6, 0.2)
rad, kn, da = 0.5, 1e6, float(ARGV()[0])
p = SPHERE((0, 0, 2 * rad), rad, mat, 1)
OBSTACLE([(-1, -1, 0, 1, -1, 0, 0, 1, 0)], 2)
GRANULAR(0, 0, kn, da, 0.0)
GRAVITY(0.0, 0.0, -10.0)
hcrit = CRITICAL()
m = 1000.0 * 4.0 / 3.0 * math.pi * rad ** 3
"""


@pytest.mark.parametrize("damper", [0.0, 1.0])
def test_critical_counts_the_pairings_that_can_act(tmp_path, damper):
    """CRITICAL() of a contact-only model: (2/w)(sqrt(1 + xi^2) - xi) with w = sqrt(k/m) and xi the damper ratio
    against the obstacle (m_eff = m); the sphere-sphere pairing (same colour, m_eff = m/2) gives a larger step."""
    ns = run(tmp_path, BOUNCE, [str(damper)])
    w = math.sqrt(1e6 / ns["m"])
    expected = (2.0 / w) * (math.sqrt(1.0 + damper ** 2) - damper)
    assert abs(ns["hcrit"] - expected) <= 1e-14 * expected, (ns["hcrit"], expected)


def test_critical_of_springs_and_contacts_is_the_smaller(tmp_path):
    body = BOUNCE + "q = SPHERE((5, 0, 2 * rad), rad, mat, 3)\nSPRING(q, (5, 0, 1), -1, (5, 0, 2), [-1, -1e10, 1, 1e10])\n" \
        "hcrit2 = CRITICAL()\n"
    ns = run(tmp_path, body, ["0.0"])
    assert ns["hcrit2"] < ns["hcrit"]
