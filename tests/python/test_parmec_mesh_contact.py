"""Contact between SPHEREs and MESH particles (issue 13 deliverable 3; fix parmec/granular 'mesh',
doc/fix_parmec_granular.md, doc/parmec_front_end.md): the MESH body's boundary triangles follow its rigid body,
spheres touching them get the GRANULAR law of the obstacles and the reaction goes onto the body.
References: the same drop on an OBSTACLE with the same triangles, momentum conservation, the two-body
restitution closed form, the torque r x F of a frictionless impact, 1 vs 2 MPI ranks, restart = split run."""
import math

import pytest

from dembridge import new_lammps
from dembridge.parmec import ParmecError, run_script
from dembridge.parmec import vtk_output
from parmec_contact_runs import atoms_by_id, fix_error, histories_on_ranks


# a 2 x 2 x 1 box, top face z = 0, centre (0, 0, -0.5): an 8-node hexahedron
BOX_NODES = [-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0]
BOX_ELEMENT = "[8, 0, 1, 2, 3, 4, 5, 6, 7, m]"


def box_triangles():
    """The box's boundary triangles exactly as the front end fans them (the OBSTACLE of the reference run)."""
    faces = vtk_output.boundary_faces([8, 0, 1, 2, 3, 4, 5, 6, 7, 0])
    tris = [t for f in faces for t in vtk_output.fan(f)]
    return [tuple(float(BOX_NODES[3 * n + c]) for n in t for c in range(3)) for t in tris]


def run(tmp_path, body, argv=(), name="model.py"):
    script = tmp_path / name
    script.write_text("import math\n" + body)
    return run_script(str(script), list(argv), workdir=str(tmp_path / ("wd_" + name)))


DROP = """
m = MATERIAL(1000.0, 1e9, 0.25)
r, k = 0.1, 1e6
p = SPHERE((0.3, 0.2, r + 0.01), r, m, 1)
VELOCITY(p, (0.5, 0.2, -1.0))
if ARGV()[0] == 'mesh':
    b = MESH(%s, %s, m, 2)
    RESTRAIN(b, [1, 0, 0, 0, 1, 0, 0, 0, 1], [1, 0, 0, 0, 1, 0, 0, 0, 1])
else:
    OBSTACLE(%r, 2)
GRANULAR(1, 2, k, 0.0, 0.3)  # no damping: m_eff (sphere vs body, sphere vs obstacle) does not enter the law
GRAVITY(0.0, 0.0, -10.0)
h = 2e-5
H = [HISTORY(s, p) for s in ('PX', 'PY', 'PZ', 'VX', 'VY', 'VZ', 'OX', 'OY', 'OZ')]
DEM(0.08, h)
"""


def test_drop_on_a_restrained_mesh_box_equals_the_drop_on_the_same_obstacle(tmp_path):
    """A sphere thrown (gravity, friction 0.3, bounces and slides) on the top of a fully RESTRAINed MESH box and on
    an OBSTACLE made of the same triangles: position, velocity and spin histories equal to 1e-12 (relative to
    their largest value); the sphere did touch (it bounced)."""
    body = DROP % (BOX_NODES, BOX_ELEMENT, box_triangles())
    a = run(tmp_path, body, ["mesh"], "mesh.py")
    b = run(tmp_path, body, ["obstacle"], "obstacle.py")
    assert max(a["H"][5]) > 0.5  # VZ rebounded
    for ha, hb in zip(a["H"], b["H"]):
        scale = max(abs(v) for v in hb)
        assert len(ha) == len(hb) > 100
        assert max(abs(u - w) for u, w in zip(ha, hb)) <= 1e-12 * scale


FREE = """
m = MATERIAL(1000.0, 1e9, 0.25)
light = MATERIAL(float(ARGV()[1]), 1e9, 0.25)
r, k, z = 0.1, 1e6, float(ARGV()[0])
p = SPHERE((float(ARGV()[2]), 0.1, r + 0.01), r, m, 1)
VELOCITY(p, (0.3, 0.0, -2.0))
b = MESH(%s, %s, light, 2)
if ARGV()[4] == 'norot':
    RESTRAIN(b, None, [1, 0, 0, 0, 1, 0, 0, 0, 1])
GRANULAR(1, 2, k, z, float(ARGV()[3]))
ms = 1000.0 * 4.0 / 3.0 * math.pi * r ** 3
h = 1e-5
S = [HISTORY(s, p) for s in ('PX', 'PY', 'PZ', 'VX', 'VY', 'VZ', 'FX', 'FY', 'FZ', 'TX', 'TY', 'TZ')]
B = [HISTORY(s, b) for s in ('PX', 'PY', 'PZ', 'VX', 'VY', 'VZ', 'FX', 'FY', 'FZ', 'TX', 'TY', 'TZ', 'OX', 'OY', 'OZ')]
DEM(0.03, h)
""" % (BOX_NODES, BOX_ELEMENT.replace(", m]", ", light]"))


def test_free_mesh_body_conserves_momentum_and_rebounds_with_the_two_body_restitution(tmp_path):
    """A sphere hits a free-flying MESH box (no gravity, 1.25x the sphere's mass, its rotation restrained):
    the total momentum is conserved to 1e-12 at every row (the reaction reaches the body whole), and the normal
    relative velocity rebounds with exp(-pi z / sqrt(1 - z^2)) within 0.5 % (the two-body closed form: the damper
    uses m_eff = m_s m_b / (m_s + m_b); with m_s, as against an obstacle, it would be 0.25, not 0.37)."""
    z = 0.3
    ns = run(tmp_path, FREE, [str(z), "1.3089969389957472", "0.0", "0.0", "norot"])  # box mass 4 * 1.309
    ms, S, B = ns["ms"], ns["S"], ns["B"]
    mb = 4.0 * 1.3089969389957472
    p0 = [ms * v for v in (0.3, 0.0, -2.0)]
    worst = 0.0
    for n in range(len(S[0])):
        for c in range(3):
            worst = max(worst, abs(ms * S[3 + c][n] + mb * B[3 + c][n] - p0[c]))
    assert worst <= 1e-12 * math.hypot(*p0), worst
    rel = S[5][-1] - B[5][-1]
    assert rel > 0  # separated
    assert abs(rel / 2.0 - math.exp(-math.pi * z / math.sqrt(1 - z * z))) < 0.005 * rel / 2.0


def test_off_centre_impact_turns_the_body_with_the_torque_r_cross_f(tmp_path):
    """A frictionless sphere hits a free MESH box 0.7 off its centre: in every step the torque on the body about its
    centre equals (x_s - x_b) x F_b (the force on a frictionless contact acts along the normal through the
    sphere's centre; positions of the evaluation x_{n+1/2} = x_{n+3/2} - h v_{n+1}) to 1e-10 of the largest
    torque, F_b = -F_s to 1e-12, and the body spins."""
    ns = run(tmp_path, FREE, ["0.2", "1.3089969389957472", "0.7", "0.0", "free"])
    S, B, h = ns["S"], ns["B"], ns["h"]
    tmax = max(math.sqrt(B[9][n] ** 2 + B[10][n] ** 2 + B[11][n] ** 2) for n in range(len(B[0])))
    fmax = max(abs(v) for v in B[8])
    assert tmax > 1e2 and fmax > 1e2
    worst_t = worst_f = 0.0
    for n in range(1, len(S[0])):
        xs = [S[c][n] - h * S[3 + c][n] for c in range(3)]
        xb = [B[c][n] - h * B[3 + c][n] for c in range(3)]
        a = [xs[c] - xb[c] for c in range(3)]
        f = [B[6 + c][n] for c in range(3)]
        rxf = [a[1] * f[2] - a[2] * f[1], a[2] * f[0] - a[0] * f[2], a[0] * f[1] - a[1] * f[0]]
        worst_t = max(worst_t, max(abs(rxf[c] - B[9 + c][n]) for c in range(3)))
        worst_f = max(worst_f, max(abs(S[6 + c][n] + B[6 + c][n]) for c in range(3)))
    assert worst_t <= 1e-10 * tmax, (worst_t, tmax)
    assert worst_f <= 1e-12 * fmax, (worst_f, fmax)
    assert abs(B[13][-1]) > 0.1  # OY: turned about y by the impact at x = 0.7


PILE = """
m = MATERIAL(1000.0, 1e9, 0.25)
light = MATERIAL(10.0, 1e9, 0.25)
r = 0.1
b = MESH(%s, %s, light, [2])
RESTRAIN(b, [0, 0, 1], [1, 0, 0, 0, 1, 0])  # slides and spins in its plane, dragged by the spheres
spheres = []
for i in range(4):
    for j in range(4):
        s = SPHERE((-0.75 + 0.5 * i, -0.75 + 0.5 * j, r - 0.001), r, m, 1 + (i + j) %% 2)
        VELOCITY(s, (3.0 if j %% 2 else -3.0, 0.5 * (i - 1.5), 0.0), (0.0, 0.0, 5.0 * (j - 1.5)))
        spheres.append(s)
GRANULAR(1, 2, 1e6, 0.5, 0.4)
GRANULAR(0, 0, 1e6, 0.3, 0.2)
GRAVITY(0.0, 0.0, -10.0)
H = [HISTORY(s, q) for q in spheres + [b] for s in ('PX', 'PY', 'PZ', 'VX', 'VY', 'VZ', 'OX', 'OY', 'OZ')]
DEM(0.1, 2e-5, 0.01)
""" % (BOX_NODES, BOX_ELEMENT.replace(", m]", ", light]"))


@pytest.mark.two_cores
def test_one_and_two_ranks_agree(tmp_path):
    """16 spheres sliding and spinning at 3 m/s across a MESH box (restrained to its plane, dragged by them), across
    the rank boundary: every HISTORY value of the spheres and the box on 1 and 2 MPI ranks within 1e-12."""
    out = histories_on_ranks(tmp_path, PILE)
    moved = max(abs(v) for v in out[1][-6]) + max(abs(v) for v in out[1][-1])  # the box's VX, OZ
    assert moved > 1e-2, moved
    worst = 0.0
    for a, b in zip(out[1], out[2]):
        for u, w in zip(a, b):
            worst = max(worst, abs(u - w) / max(1.0, abs(u)))
    assert worst <= 1e-12, worst


# ------------------------------------------------------------------------------------------ LAMMPS level

def mesh_words(tag=3, centre=(0.0, 0.0, -0.5), color=2):
    tris = box_triangles()
    return (f"mesh {tag} {len(tris)} " + " ".join(repr(v) for t in tris for v in t) + f" color {color} center "
            + " ".join(repr(c) for c in centre))


def deck(lmp, fixes_only=False):
    if not fixes_only:
        for c in ["units si", "atom_style bpm/sphere", "atom_modify map array", "boundary m m m",
                  "region b block -2 2 -2 2 -2 2", "create_box 2 b",
                  "create_atoms 1 single -0.2 0.1 0.09996", "create_atoms 1 single 0.3 -0.2 0.09996",
                  "create_atoms 2 single 0.0 0.0 -0.5",
                  "set type 1 diameter 0.2", "set type 2 diameter 1.0", "set group all density 1000",
                  "set type 2 density 100",
                  "velocity all set 0.5 0.2 0.0", "set atom 3 vx 0 vy 0 vz 0",
                  "fix PC all property/atom i_pmcolor ghost yes", "set type 1 i_pmcolor 1", "set type 2 i_pmcolor 0"]:
            lmp.command(c)
    else:  # the colours come back from the restart file with the property fix of the same ID
        lmp.command("fix PC all property/atom i_pmcolor ghost yes")
    for c in ["comm_modify vel yes", "pair_style zero 0.2", "pair_coeff * *", "neighbor 0.01 bin",
              "neigh_modify delay 0 every 1 check yes", "timestep 2e-5",
              "fix G all parmec/granular color i_pmcolor pairing 1 2 spring 1e6 damper 0.5 friction 0.4 "
              "pairing 1 1 spring 1e6 " + mesh_words(),
              "fix R all parmec/rigid gravity 0 0 -10 restrain 3 linear 0 0 1"]:
        lmp.command(c)


def test_restart_with_mesh_contacts_continues_bitwise(tmp_path):
    """Two spheres sliding with friction on a MESH box (fix parmec/rigid, restrained vertically): write_restart
    at step 1000 of 2000 and read back with the same fixes: positions and velocities of spheres and box equal
    the split run (1000 + 1000 steps in one process) bitwise; the contacts' tangential springs were carried."""
    a = new_lammps()
    deck(a)
    a.command("run 1000")
    assert a.extract_fix("G", 0, 1, 5) == 2  # both spheres on the box
    a.command("run 1000")
    ref = atoms_by_id(a, "x", "v")
    a.close()
    b = new_lammps()
    deck(b)
    b.command("run 1000")
    b.command(f"write_restart {tmp_path / 'r.bin'}")
    b.close()
    c = new_lammps()
    c.command(f"read_restart {tmp_path / 'r.bin'}")
    deck(c, fixes_only=True)
    c.command("run 1000")
    got = atoms_by_id(c, "x", "v")
    c.close()
    assert abs(ref[2, 3]) > 1e-3  # the box was dragged
    assert (got == ref).all(), abs(got - ref).max()


LAMMPS_BAD = [
    ("pairing 2 2 spring 1e6 " + mesh_words(3) + " " + mesh_words(4, color=2),
     "MESH bodies 3 and 4: the pairing of their colours 2 and 2 has spring > 0"),
    ("pairing 1 2 spring 1e6 mesh 3 1 0 0 0 1 0 0 0 1 0 color 2", "expected 'center X Y Z'"),
    ("pairing 1 2 spring 1e6 mesh 3 1 0 0 0 1 0 0 0 1 0 center 0 0 0", "expected 'color C' or 'colors C1 ... CN'"),
    ("pairing 1 2 spring 1e6 mesh 3 1 0 0 0 1 0 0 2 0 0 color 2 center 0 0 0", "mesh 3"),
    ("pairing 1 2 spring 1e6 mesh 0 1 0 0 0 1 0 0 0 1 0 color 2 center 0 0 0", "must be >= 1"),
]


@pytest.mark.parametrize("defs,message", LAMMPS_BAD, ids=[f"lmp_bad{i}" for i in range(len(LAMMPS_BAD))])
def test_lammps_bad_input(defs, message):
    err = fix_error(defs)
    assert message in err, err


def test_lammps_mesh_bodies_need_fix_parmec_rigid():
    """A MESH body needs fix parmec/rigid, with its atom in that fix's group (the rotation that places it), and
    colour <= 0 (no sphere shape)."""
    lmp = new_lammps()
    deck_cmds = ["units si", "atom_style bpm/sphere", "atom_modify map array", "region b block -2 2 -2 2 -2 2",
                 "create_box 2 b", "create_atoms 1 single 0 0 0.2", "create_atoms 2 single 0 0 -0.5",
                 "set group all diameter 0.2", "set group all density 1000", "comm_modify vel yes",
                 "pair_style zero 0.2", "pair_coeff * *",
                 "fix G all parmec/granular pairing 1 1 spring 1e6 " + mesh_words(2, color=1), "fix I all nve/sphere"]
    for c in deck_cmds:
        lmp.command(c)
    with pytest.raises(Exception) as e:
        lmp.command("run 1")
    assert "MESH bodies need fix parmec/rigid" in str(e.value), str(e.value)
    lmp.command("unfix I")
    lmp.command("group spheres type 1")
    lmp.command("fix R spheres parmec/rigid")
    with pytest.raises(Exception) as e:  # 'color type': the body atom has colour 2
        lmp.command("run 1")
    assert "mesh 2: the atom of a MESH body must have colour <= 0" in str(e.value), str(e.value)
    for c in ["unfix G", "fix PC all property/atom i_pmcolor ghost yes", "set atom 1 i_pmcolor 1",
              "fix G all parmec/granular color i_pmcolor pairing 1 1 spring 1e6 " + mesh_words(2, color=1),
              "unfix R", "fix R spheres parmec/rigid"]:
        lmp.command(c)
    with pytest.raises(Exception) as e:
        lmp.command("run 1")
    assert "mesh 2: the body atom is not in the group of fix R parmec/rigid" in str(e.value), str(e.value)
    lmp.close()


# ------------------------------------------------------------------------------------------ front end bad input

PRE = "m = MATERIAL(1000.0, 1e9, 0.25)\np = SPHERE((0, 0, 2), 0.1, m, 1)\n"
CUBE = "MESH([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1], [8, 0, 1, 2, 3, 4, 5, 6, 7, m], m, %s)\n"
BAD = [
    (CUBE % 2 + CUBE % 3 + "GRANULAR(2, 3, 1e5)\nDEM(0.001, 1e-4)",
     "DEM: MESH particles 1 and 2: the GRANULAR pairing of their colours (2, 3) has spring > 0"),
    ("GRANULAR(0, 0, 1e5)\n" + CUBE % 2 + CUBE % 2 + "DEM(0.001, 1e-4)",
     "DEM: MESH particles 1 and 2: the GRANULAR pairing of their colours (2, 2) has spring > 0"),
    (CUBE % "[2, 4, 0, 1, 2, 3, 5]" + CUBE % 3 + "GRANULAR(3, 5, 1e5)\nDEM(0.001, 1e-4)",
     "DEM: MESH particles 1 and 2: the GRANULAR pairing of their colours (5, 3) has spring > 0"),
]


@pytest.mark.parametrize("body,message", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_front_end_mesh_mesh_contact_is_refused(tmp_path, body, message):
    with pytest.raises(ParmecError) as e:
        run(tmp_path, PRE + body + "\n")
    assert message in str(e.value), str(e.value)


CUBE2 = ("MESH([3, 0, 0, 4, 0, 0, 4, 1, 0, 3, 1, 0, 3, 0, 1, 4, 0, 1, 4, 1, 1, 3, 1, 1], [8, 0, 1, 2, 3, 4, 5, 6, 7, m], "
         "m, 2)\n")
FIXED = "[1, 0, 0, 0, 1, 0, 0, 0, 1]"


def test_a_pairing_switched_off_allows_two_mesh_bodies(tmp_path):
    """GRANULAR(0, 0, k) with two MESH particles of colour 2 runs once GRANULAR(2, 2, 0.0) switches their pair off;
    the sphere (colour 1, critical damping) comes to rest on the first box's top face z = 1 with the static sag
    m g / k (1e-6)."""
    body = ("m = MATERIAL(1000.0, 1e9, 0.25)\np = SPHERE((0.3, 0.6, 1.2), 0.1, m, 1)\nGRANULAR(0, 0, 1e5)\n"
            + CUBE % 2 + CUBE2 + "GRANULAR(2, 2, 0.0)\n"
            + f"RESTRAIN(1, {FIXED}, {FIXED})\nRESTRAIN(2, {FIXED}, {FIXED})\n"
            + "GRAVITY(0.0, 0.0, -10.0)\nZ = HISTORY('PZ', p)\nDEM(0.5, 1e-4)\n")
    ns = run(tmp_path, body)
    ms = 1000.0 * 4.0 / 3.0 * math.pi * 0.1 ** 3
    assert abs(ns["Z"][-1] - (1.1 - ms * 10.0 / 1e5)) < 1e-6, ns["Z"][-1]
