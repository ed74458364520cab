"""fix mbdyn ... modal FEM-FILE mesh MESH-ID: an STL plate whose vertices are the FEM nodes of a
5 x 3 grid, driven by MBDyn's modal coordinates (the test peer's clamped modal body, type modal), with
four heavy spheres landing on four of its faces (no sphere touches another or an edge). Two modes in z
whose generalized forces have closed forms in the spheres' wall forces f_i and contact points c_i:
  mode 1, phi = (0, 0, 1):    p1 = -sum_i f_i,z                (the plate's z force)
  mode 2, phi = (0, 0, x/L):  p2 = -sum_i (x(c_i) / L) f_i,z   (phi is linear, so the barycentric split
                                                              of a contact is phi at the contact point)
with f_i = the dumped force of sphere i less its weight and c_i = its centre projected on the face under
it (from the mesh dump). Also: every vertex = X + q1 phi1 + q2 phi2 of the coordinates sent."""
import os
import subprocess

import pytest

from dembridge import plugin_path, read_dump_atoms
from gran_deck import GRAN_HEAD, HOOKE_ONE_TYPE
from test_fix_mbdyn import PEER, error_line, run_lammps, sockdir  # noqa: F401 (fixture)
from test_mbdyn_mapping_mesh import read_stl

pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")

NX, NY, H, L = 5, 3, 0.1, 0.4
R, RHO, G, DT, STEPS = 0.03, 10000.0, 9.81, 1e-3, 300
CELLS = ((0, 0), (2, 0), (1, 1), (3, 1))  # a sphere above the centroid of triangle (A, B, C) of each cell


def node(i, j):
    return (i * H, (j - 1) * H, 0.0)


def phi(m, x):
    return 1.0 if m == 0 else x / L


def write_fem(path):
    nodes = [node(i, j) for j in range(NY) for i in range(NX)]
    lines = ["** RECORD GROUP 1, HEADER", f"REV0 {len(nodes)} 2 0 0 0", "** RECORD GROUP 2, FINITE ELEMENT NODE LIST",
             " ".join(str(k + 1) for k in range(len(nodes)))]
    for g, c in ((5, 0), (6, 1), (7, 2)):
        lines += [f"** RECORD GROUP {g}, NODAL COORDINATES"] + [repr(n[c]) for n in nodes]
    lines += ["** RECORD GROUP 8, MODE SHAPES"]
    for m in range(2):
        lines += [f"**  MODE {m + 1}"] + [f"0. 0. {phi(m, n[0])!r} 0. 0. 0." for n in nodes]
    open(path, "w").write("\n".join(lines + ["** END OF FILE"]) + "\n")


def write_stl(path):
    out = ["solid plate"]
    for j in range(NY - 1):
        for i in range(NX - 1):
            a, b, c, d = node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)
            for tri in ((a, b, c), (a, c, d)):
                out += ["facet normal 0 0 1", "outer loop"] + [f"vertex {v[0]!r} {v[1]!r} {v[2]!r}" for v in tri]
                out += ["endloop", "endfacet"]
    open(path, "w").write("\n".join(out + ["endsolid plate"]) + "\n")


def model(sock, d, extra=""):
    """The contact law, the plate, its wall and fix mbdyn ... modal: what a deck after read_restart defines again."""
    return f"""{HOOKE_ONE_TYPE}
neighbor 0.005 bin
timestep {DT}
fix plate all mesh/surface/stress file {d}/plate.stl type 1
fix walls all wall/gran model hooke tangential history mesh n_meshes 1 meshes plate
fix I all nve/sphere
fix M all mbdyn path {sock} modal {d}/plate.fem modes 2 type modal mesh plate connect_timeout 60 io_timeout 60 {extra}
fix g all gravity {G} vector 0 0 -1
"""


def spheres_deck():
    """The box and the four spheres, 1 mm above their faces."""
    spheres = "\n".join(f"create_atoms 1 single {(i + 2 / 3) * H!r} {(j - 1 + 1 / 3) * H!r} {R + 1e-3!r} units box"
                        for i, j in CELLS)
    return f"""{GRAN_HEAD}
region box block -0.1 0.5 -0.2 0.2 -0.2 0.2 units box
create_box 1 box
{spheres}
set type 1 diameter {2 * R}
set type 1 density {RHO}
"""


def deck(sock, d, extra="", steps=STEPS):
    return f"""{spheres_deck()}{model(sock, d, extra)}fix D all mesh/dump 10 stl {d}/mesh*.stl plate
dump A all custom 10 {d}/atoms.*.dump id radius mass x y z fx fy fz
dump_modify A format float %.17g
run {steps}
"""


def peer_args(sock, d, steps=STEPS, trajectory="modes.txt"):
    return [PEER, "--path", sock, "--steps", str(steps), "--dt", repr(DT), "--modal-mass", "1,1",
            "--modal-stiffness", "3000,3000", "--modal-damping", "20,20", "--trajectory", f"{d}/{trajectory}",
            "--accept-timeout", "20", "--io-timeout", "60"]


def peer(sock, d, steps=STEPS):
    return subprocess.Popen(peer_args(sock, d, steps), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def normal(tri):
    a, b, c = tri
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    s = sum(x * x for x in n) ** 0.5
    return [x / s for x in n]


def coupled(d, nprocs=1, extra="", stl=None, steps=STEPS):
    write_fem(f"{d}/plate.fem")
    write_stl(f"{d}/plate.stl")
    if stl:
        stl(f"{d}/plate.stl")
    sock = f"{d}/m.sock"
    pr = peer(sock, d, steps)
    rc, out, _ = run_lammps(deck(sock, d, extra, steps), d, nprocs=nprocs, timeout=120)
    log = pr.communicate(timeout=60)[0]
    return rc, out, log, pr.returncode


def test_mesh_vertices_follow_the_modes_and_p_is_the_virtual_work_of_the_wall_forces(sockdir):  # noqa: F811
    rc, out, log, prc = coupled(sockdir)
    assert rc == 0 and prc == 0, (error_line(out), out[-2000:], log)
    rows = [[float(v) for v in l.split()] for l in open(f"{sockdir}/modes.txt") if not l.startswith("#")]
    assert len(rows) == STEPS + 1
    worst_x = worst_p = 0.0
    pmax = max(abs(r[7]) for r in rows)
    loaded = 0
    for k in range(10, STEPS + 1, 10):
        q = rows[k - 1][1:3]  # the coordinates sent at step k: MBDyn's at the end of step k - 1
        mesh = read_stl(f"{sockdir}/mesh{k}.stl")
        for tri in mesh:
            for v in tri:
                want = (v[0], v[1], q[0] * phi(0, v[0]) + q[1] * phi(1, v[0]))
                worst_x = max(worst_x, max(abs(v[c] - want[c]) for c in range(3)))
        (_, a), = read_dump_atoms(f"{sockdir}/atoms.{k}.dump")
        p = [0.0, 0.0]
        for i in range(len(a["id"])):
            fz = a["fz"][i] + a["mass"][i] * G  # the wall's force on the sphere
            if fz == 0.0:
                continue
            under = [t for t in mesh if min(x[0] for x in t) <= a["x"][i] <= max(x[0] for x in t)
                     and min(x[1] for x in t) <= a["y"][i] <= max(x[1] for x in t)]
            # the triangle under the centre: the one whose (x, y) contains it
            def inside(t, px=a["x"][i], py=a["y"][i]):
                s = [(t[(e + 1) % 3][0] - t[e][0]) * (py - t[e][1]) - (t[(e + 1) % 3][1] - t[e][1]) * (px - t[e][0])
                     for e in range(3)]
                return all(x > 0 for x in s) or all(x < 0 for x in s)
            tri, = [t for t in under if inside(t)]
            n, centre = normal(tri), (a["x"][i], a["y"][i], a["z"][i])
            xc = centre[0] - sum((centre[c] - tri[0][c]) * n[c] for c in range(3)) * n[0]  # centre on the face
            p[0] -= fz
            p[1] -= xc / L * fz
        loaded += p[0] != 0.0
        worst_p = max(worst_p, max(abs(p[m] - rows[k][7 + m]) for m in range(2)) / pmax)
    print(f"modal mesh: vertices {worst_x:.2e} m, p {worst_p:.2e} of max |p1| = {pmax:.3g} N; {loaded} of "
          f"{STEPS // 10} dumped steps loaded; q1 at the end {rows[-1][1]:.3e}")
    assert loaded >= 20 and rows[-1][1] < -1e-3  # the spheres rest on the plate and push it down
    assert worst_x <= 1e-15
    assert worst_p <= 1e-12


@pytest.mark.two_cores
def test_two_ranks_send_the_same_generalized_forces_bit_for_bit(sockdir):  # noqa: F811
    runs = []
    for n in (1, 2):
        d = os.path.join(sockdir, str(n))
        os.makedirs(d)
        rc, out, log, prc = coupled(d, nprocs=n, steps=60)  # the spheres land at step 15
        assert rc == 0 and prc == 0, (error_line(out), out[-2000:], log)
        runs.append(open(f"{d}/modes.txt").read())
    assert runs[0] == runs[1]  # q, q', q'' and p of every step, at 17 digits
    assert float(runs[0].splitlines()[-1].split()[7]) < -1.0  # with the spheres on the plate


@pytest.mark.parametrize("case", ["no mesh", "vertex off its node"])
def test_bad_mesh_is_an_error_naming_it(case, sockdir):  # noqa: F811
    if case == "no mesh":
        write_fem(f"{sockdir}/plate.fem")
        write_stl(f"{sockdir}/plate.stl")
        rc, out, _ = run_lammps(deck(f"{sockdir}/m.sock", sockdir).replace("mesh plate connect", "mesh lid connect"),
                                sockdir, timeout=60)
        print(error_line(out))
        assert rc != 0 and "lid" in error_line(out), out[-2000:]
        return
    def shift(path):  # the corner (0.4, 0, 0) of two triangles, 1 mm off its FEM node
        text = open(path).read()
        open(path, "w").write(text.replace("vertex 0.4 0.0 0.0\n", "vertex 0.4 0.0 0.001\n"))
    rc, out, log, _ = coupled(sockdir, stl=shift)
    err = error_line(out)
    print(err)
    assert rc != 0 and "mesh plate" in err and "0.001" in err, out[-2000:]
