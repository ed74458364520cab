"""fix mbdyn ... mapping MESH-ID points M: MBDyn's `external structural mapping` mapped points drive
the vertices of a fix mesh/surface/stress mesh, which deforms. Driven by the kinematics the real
MBDyn 1.7.3 sent in the recorded cantilever run (tests/data/mbdyn-ext/mapping_beam: 15 mapped
points, the 16-triangle grid grid_rest.stl whose vertices are the mapped points at rest,
triangles.csv naming each triangle's points):
  * every vertex of the mesh (written by fix mesh/dump at 17 digits) equals its mapped point of
    that exchange exactly, and between two exchanges (sub-steps) the cubic Hermite of the two poses
    (its derivative for the vertex velocities); the loads sent are then the sub-step average;
  * with particles resting on the deforming mesh, the loads answered per mapped point sum to minus
    the particles' wall forces (their total force less their weight; they do not touch each other),
    and their moments about the origin (at the points' positions) to the moment of the wall contacts
    on the mesh (fix mesh/surface/stress's, about its reference point, moved to the origin), each to
    1e-12 of its largest value. (Not to the particles' x x f + torque: their torques put the
    tangential force at the contact law's arm, not at the contact point; 5e-6 relative here);
  * 1 rank and 2 ranks answer the same loads to 1e-12; tight coupling: the recorded command sequence,
    at each step's end the vertices at the converged points and the converged loads minus the wall force;
  * bad input is an ERROR naming the argument."""
import csv
import gzip
import math
import os
import re

import pytest

from dembridge import plugin_path
from mbdyn_transcripts import FakeMbdyn
from gran_deck import GRAN_HEAD, HOOKE_ONE_TYPE
from test_fix_mbdyn import error_line, parse_thermo, run_lammps
from test_mbdyn_refnode_forces import sockdir  # noqa: F401 (the fixture: a short folder for the socket)

pytestmark = pytest.mark.skipif(not os.path.exists(plugin_path()), reason="needs the plugin (build dembridgeplugin)")

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "mapping_beam")
STL = os.path.join(DATA, "grid_rest.stl")
M_POINTS, G = 15, 9.81
PARTICLES = [(0.3, 0.03), (0.6, -0.05), (1.0, 0.0), (1.3, 0.06)]  # (x, y) on the plate, apart from each other
RADIUS = 0.02


def transcript(coupling="loose"):
    with gzip.open(os.path.join(DATA, f"transcript_{coupling}.csv.gz"), "rt") as f:
        return [(int(r["seq"]), r["dir"], int(r["cmd"]), r["values"].split()) for r in csv.DictReader(f)]


def messages(rows):
    """The kinematics messages: (q, qdot), each 3 M values."""
    out = []
    for _, d, c, v in rows:
        if d == "mbdyn->peer" and c in (2, 6):
            vals = [float(x) for x in v]
            out.append((vals[:3 * M_POINTS], vals[3 * M_POINTS:6 * M_POINTS]))
    return out


def triangles():
    with open(os.path.join(DATA, "triangles.csv")) as f:
        return [(int(r["v0"]), int(r["v1"]), int(r["v2"])) for r in csv.DictReader(f)]


def read_stl(path):
    v = [[float(x) for x in l.split()[1:4]] for l in open(path) if l.strip().startswith("vertex")]
    return [v[i:i + 3] for i in range(0, len(v), 3)]


def read_vtk_velocity(path):
    """The per-node velocities of fix mesh/dump vtk (3 per triangle, corner order)."""
    lines = open(path).read().splitlines()
    i = lines.index("VECTORS velocity double")
    out = []
    for l in lines[i + 1:]:
        p = l.split()
        if len(p) != 3:
            break
        out.append([float(x) for x in p])
    return out


def deck(sock, steps, fix_extra="", particles=True, procs="", dump=None, mesh_line=None):
    atoms = ""
    if particles:
        atoms = "\n".join(f"create_atoms 1 single {x} {y} {RADIUS - 1e-3} units box" for x, y in PARTICLES)
        atoms += f"\nset type 1 diameter {2 * RADIUS}\nset type 1 density 100000\n"
    mesh = mesh_line or f"fix plate all mesh/surface/stress file {STL} type 1"
    return f"""{GRAN_HEAD}
{procs}
region box block -0.2 1.8 -0.3 0.3 -0.2 0.3 units box
create_box 1 box
{atoms}
{HOOKE_ONE_TYPE}
neighbor 0.005 bin
timestep 0.002
{mesh}
fix walls all wall/gran model hooke tangential history mesh n_meshes 1 meshes plate
fix I all nve/sphere
fix M all mbdyn path {sock} mapping plate points {M_POINTS} orientation none connect_timeout 60 io_timeout 60 {fix_extra}
fix g all gravity {G} vector 0 0 -1
{dump or ''}
variable fzw atom fz+mass*{G}
compute s all reduce sum fx fy v_fzw
thermo_style custom step c_s[1] c_s[2] c_s[3] f_plate[1] f_plate[2] f_plate[3] f_plate[4] f_plate[5] f_plate[6] &
  f_plate[7] f_plate[8] f_plate[9]
thermo_modify format float %.17g
thermo 1
run {steps}
"""


def couple(sockdir, steps, nprocs=1, coupling="loose", answers_out=None, rows=None, **kw):
    rows = rows or transcript(coupling)
    sock = os.path.join(sockdir, "m.sock")
    fake = FakeMbdyn(sock, rows, timeout=30)
    rc, out, secs = run_lammps(deck(sock, steps, **kw), sockdir, nprocs=nprocs, timeout=120)
    answers = fake.join()
    assert fake.error is None, (fake.error, out[-3000:])
    assert rc == 0, out[-3000:]
    if answers_out is not None:
        answers_out.extend(answers)
    loads = [v for _, c, v in answers if c in (2, 6)]
    return rows, loads, parse_thermo(out, 13), secs


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


@pytest.mark.two_cores
def test_vertices_follow_the_mapped_points_and_loads_are_the_wall_forces(sockdir):
    rows = transcript()
    steps = len(messages(rows)) - 1  # loose, one sub-step: LAMMPS step n holds message n (0: t0)
    dump = f"fix D all mesh/dump 1 stl {sockdir}/mesh*.stl plate"
    results = {}
    for nprocs in (1, 2):
        rows, loads, thermo, secs = couple(sockdir, steps, nprocs, dump=dump if nprocs == 1 else None,
                                           procs="processors 2 1 1" if nprocs == 2 else "")
        assert len(loads) == steps + 1
        results[nprocs] = loads
        if nprocs == 1:
            msgs, tris = messages(rows), triangles()
            worst_vertex = 0.0
            for n, (q, _) in enumerate(msgs):
                mesh = read_stl(f"{sockdir}/mesh{n}.stl")
                assert len(mesh) == len(tris)
                for t, corners in enumerate(tris):
                    for k, j in enumerate(corners):
                        worst_vertex = max(worst_vertex, max(abs(mesh[t][k][c] - q[3 * j + c]) for c in range(3)))
            assert worst_vertex == 0.0, worst_vertex
            fscale = mscale = 0.0
            worst_f = worst_m = 0.0
            touching = 0
            for n, (q, _) in enumerate(msgs):
                p = loads[n]
                F = [sum(p[3 * j + c] for j in range(M_POINTS)) for c in range(3)]
                Mo = [0.0, 0.0, 0.0]
                for j in range(M_POINTS):
                    m = cross(q[3 * j:3 * j + 3], p[3 * j:3 * j + 3])
                    Mo = [Mo[c] + m[c] for c in range(3)]
                # the particles' wall force; the mesh's moment of its wall contacts, moved to the origin
                fp, fm, mr, r = thermo[n][0:3], thermo[n][3:6], thermo[n][6:9], thermo[n][9:12]
                mp = [-(mr[c] + cross(r, fm)[c]) for c in range(3)]
                fscale, mscale = max(fscale, max(map(abs, fp))), max(mscale, max(map(abs, mp)))
                worst_f = max(worst_f, max(abs(F[c] + fp[c]) for c in range(3)))
                worst_m = max(worst_m, max(abs(Mo[c] + mp[c]) for c in range(3)))
                touching += max(map(abs, fp)) > 0.1 * len(PARTICLES) * 1e5 * 4 / 3 * 3.14159 * RADIUS ** 3 * G
            print(f"mapping mesh: {steps + 1} exchanges in {secs:.1f} s, vertices vs mapped points {worst_vertex}; "
                  f"sum of point loads + particles' wall force {worst_f / fscale:.1e} of {fscale:.3g} N, moments "
                  f"{worst_m / mscale:.1e} of {mscale:.3g} N m; {touching} exchanges with the particles pressing")
            assert touching >= steps // 2, "the particles do not press on the mesh: the test checks nothing"
            assert worst_f <= 1e-12 * fscale
            assert worst_m <= 1e-12 * mscale
    scale = max(abs(x) for l in results[1] for x in l)
    worst = max(abs(a - b) for la, lb in zip(results[1], results[2]) for a, b in zip(la, lb))
    print(f"mapping mesh: 1 rank vs 2 ranks {worst / scale:.1e} of the largest point load {scale:.3g}")
    assert worst <= 1e-12 * scale


def test_tight_converged_vertices_and_loads(sockdir):
    # tight: per step, MBDyn's iterates (command 2) until the converged one is answered with 6; the
    # convergence test sees the poses only (tolerance 1e-13 as for the wall of atoms), so fix mbdyn
    # answers with the recorded command sequence; at each step's end the mesh is at the last iterate
    # and the converged loads are minus the particles' wall force
    rows = transcript("tight")
    steps = sum(1 for _, d, c, _ in rows if d == "peer->mbdyn" and c == 6) - 1
    dump = f"fix D all mesh/dump 1 stl {sockdir}/mesh*.stl plate"
    answers = []
    _, _, thermo, secs = couple(sockdir, steps, coupling="tight", fix_extra="coupling tight tolerance 1e-13",
                                dump=dump, answers_out=answers)
    assert [(q, c) for q, c, _ in answers] == [(q, c) for q, d, c, _ in rows if d == "peer->mbdyn"]
    # the kinematics message just before each answer with command 6 is the step's converged pose
    converged, last = [], None
    for _, d, c, v in rows:
        if d == "mbdyn->peer" and c in (2, 6):
            last = [float(x) for x in v][:3 * M_POINTS]
        elif d == "peer->mbdyn" and c == 6:
            converged.append(last)
    final = [v for _, c, v in answers if c == 6]
    assert len(converged) == len(final) == steps + 1
    tris = triangles()
    worst_vertex = worst_f = fscale = 0.0
    for n, q in enumerate(converged):
        mesh = read_stl(f"{sockdir}/mesh{n}.stl")
        worst_vertex = max(worst_vertex, max(abs(mesh[t][k][c] - q[3 * j + c]) for t, cs in enumerate(tris)
                                             for k, j in enumerate(cs) for c in range(3)))
        F = [sum(final[n][3 * j + c] for j in range(M_POINTS)) for c in range(3)]
        fp = thermo[n][0:3]
        fscale = max(fscale, max(map(abs, fp)))
        worst_f = max(worst_f, max(abs(F[c] + fp[c]) for c in range(3)))
    print(f"mapping mesh tight: {len(answers)} answers in {secs:.1f} s; converged vertices vs MBDyn's points "
          f"{worst_vertex}; converged loads + particles' wall force {worst_f / fscale:.1e} of {fscale:.3g} N")
    assert worst_vertex == 0.0
    assert worst_f <= 1e-12 * fscale


def test_substeps_vertices_follow_the_hermite_of_two_poses(sockdir):
    # mbdyn_dt = 4 LAMMPS steps: at s = 1 the vertices are MBDyn's points, at s = 1/2 the cubic
    # Hermite of the two poses, h00 = h01 = 1/2, h10 = -h11 = 1/8 (times T), its derivative for v
    rows = transcript()
    msgs = messages(rows)
    n_msg = len(msgs)
    dump = f"fix D all mesh/dump 2 stl {sockdir}/mesh*.stl plate\nfix V all mesh/dump 2 vtk {sockdir}/mesh*.vtk plate"
    _, loads, thermo, _ = couple(sockdir, 4 * (n_msg - 1), fix_extra="mbdyn_dt 0.008", dump=dump)
    # the loads sent per MBDyn step: the average over its 4 sub-steps of minus the particles' wall force
    worst_f = fscale = 0.0
    for m in range(1, n_msg):
        avg = [sum(thermo[4 * (m - 1) + j][c] for j in range(1, 5)) / 4 for c in range(3)]
        F = [sum(loads[m][3 * j + c] for j in range(M_POINTS)) for c in range(3)]
        fscale = max(fscale, max(map(abs, avg)))
        worst_f = max(worst_f, max(abs(F[c] + avg[c]) for c in range(3)))
    print(f"mapping mesh, 4 sub-steps: loads + the sub-step average of the particles' wall force "
          f"{worst_f / fscale:.1e} of {fscale:.3g} N")
    assert fscale > 1.0 and worst_f <= 1e-12 * fscale
    T, tris = 0.008, triangles()
    worst_end = worst_mid = worst_vend = worst_vmid = 0.0
    for m in range(1, n_msg):
        (qa, va), (qb, vb) = msgs[m - 1], msgs[m]
        end, mid = read_stl(f"{sockdir}/mesh{4 * m}.stl"), read_stl(f"{sockdir}/mesh{4 * m - 2}.stl")
        vend, vmid = read_vtk_velocity(f"{sockdir}/mesh{4 * m}.vtk"), read_vtk_velocity(f"{sockdir}/mesh{4 * m - 2}.vtk")
        for t, corners in enumerate(tris):
            for k, j in enumerate(corners):
                for c in range(3):
                    i = 3 * j + c
                    h = 0.5 * qa[i] + 0.125 * T * va[i] + 0.5 * qb[i] - 0.125 * T * vb[i]
                    dh = (-1.5 * qa[i] + 1.5 * qb[i]) / T - 0.25 * va[i] - 0.25 * vb[i]
                    worst_end = max(worst_end, abs(end[t][k][c] - qb[i]))
                    worst_mid = max(worst_mid, abs(mid[t][k][c] - h))
                    worst_vend = max(worst_vend, abs(vend[3 * t + k][c] - vb[i]))
                    worst_vmid = max(worst_vmid, abs(vmid[3 * t + k][c] - dh))
    print(f"mapping mesh, 4 sub-steps: vertices vs MBDyn's points at the exchanges {worst_end}, "
          f"vs the Hermite mid-step {worst_mid:.1e}; vertex velocities vs MBDyn's {worst_vend}, vs the Hermite "
          f"derivative mid-step {worst_vmid:.1e}")
    assert worst_end == 0.0 and worst_vend == 0.0
    assert worst_mid <= 1e-15
    assert worst_vmid <= 1e-12


BAD = [
    ("orientation", "mapping plate points 15", "orientation matrix",
     "'mapping' needs 'orientation none'"),
    ("node", "mapping plate points 15 node atom 1", "orientation none",
     "'mapping' and 'node atom 1' together"),
    ("points", "mapping plate points 2", "orientation none",
     "keyword 'mapping points' expects the number of MBDyn's mapped points (>= 3), got '2'"),
    ("points keyword", "mapping plate 15", "orientation none",
     "keyword 'mapping' expects 'mapping MESH-ID points M', got '15' after the mesh ID"),
    ("match_tolerance", "mapping plate points 15 match_tolerance -1", "orientation none",
     "keyword 'match_tolerance' expects a distance (> 0), got -1"),
    ("match_tolerance alone", "node atom 1 match_tolerance 1e-6", "orientation none",
     "'match_tolerance' is for 'mapping MESH-ID points M'"),
    ("twice", "mapping plate points 15 mapping plate points 15", "orientation none",
     "keyword 'mapping' given twice"),
    ("reference", "mapping plate points 15 reference_node yes", "orientation none",
     "'mapping' with 'reference_node yes' needs the reference node's 'orientation'"),
    ("reference body", "mapping plate points 15 reference_node yes reference atom 1", "orientation matrix",
     "'mapping' takes no 'reference atom|group'"),
    ("mesh id", "mapping nosuch points 15", "orientation none",
     "mesh ID 'nosuch' does not exist"),
    ("labels", "mapping plate points 15 labels yes", "orientation none",
     "'mapping' with 'labels yes' is not supported"),
    ("accelerations", "mapping plate points 15 accelerations yes", "orientation none",
     "'mapping' with 'accelerations yes' is not supported"),
]


@pytest.mark.parametrize("case", BAD, ids=[c[0] for c in BAD])
def test_bad_mapping_arguments(case, tmp_path):
    _, args, orient, expected = case
    text = f"""plugin load ${{plugin}}
units si
atom_style sphere
region box block -0.2 1.8 -0.3 0.3 -0.2 0.3 units box
create_box 1 box
create_atoms 1 single 0.5 0 0.1 units box
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.3
fix plate all mesh/surface/stress file {STL} type 1
fix M all mbdyn path {tmp_path}/x.sock create no {args} {orient} connect_timeout 1
run 1
"""
    rc, out, _ = run_lammps(text, str(tmp_path), timeout=60)
    err = error_line(out)
    assert rc != 0 and expected in err, out[-2000:]


def test_bad_mapping_no_stress(tmp_path):
    text = f"""plugin load ${{plugin}}
units si
atom_style sphere
region box block -0.2 1.8 -0.3 0.3 -0.2 0.3 units box
create_box 1 box
create_atoms 1 single 0.5 0 0.1 units box
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.3
fix plate all mesh/surface file {STL} type 1
fix M all mbdyn path {tmp_path}/x.sock create no mapping plate points 15 orientation none connect_timeout 1
run 1
"""
    rc, out, _ = run_lammps(text, str(tmp_path), timeout=60)
    assert rc != 0 and "mapping plate needs fix mesh/surface/stress" in error_line(out), out[-2000:]


def shifted_stl(path, old, new):
    """grid_rest.stl with every vertex line 'old' replaced by 'new'."""
    text = open(STL).read().replace(f"vertex {old}\n", f"vertex {new}\n")
    open(path, "w").write(text)


@pytest.mark.parametrize("case", ["no point", "two points"])
def test_bad_vertex_matching_names_the_vertex(case, sockdir):
    rows = transcript()
    sock = os.path.join(sockdir, "m.sock")
    stl = os.path.join(sockdir, "grid.stl")
    if case == "no point":
        shifted_stl(stl, "1.5 0.1 0.0", "1.5 0.1 0.001")  # the far tip corner, 1 mm off its point
        extra, expected = "", r"vertex \d of triangle \d+ at \(1\.5, 0\.1, 0\.001\) has no mapped point within the " \
                              r"match tolerance \(the nearest, point 15, is 0\.001 away\).*match_tolerance 1e-08"
    else:
        shifted_stl(stl, "x", "x")
        extra, expected = "match_tolerance 0.15", r"within the match tolerance of two mapped points, \d+ and \d+"
    fake = FakeMbdyn(sock, rows, timeout=30)
    rc, out, _ = run_lammps(deck(sock, 5, fix_extra=extra, particles=False,
                                 mesh_line=f"fix plate all mesh/surface/stress file {stl} type 1"), sockdir, timeout=60)
    fake.join()
    err = error_line(out)
    assert rc != 0 and "mapping plate points 15" in err and re.search(expected, err), out[-2000:]


def rot_z_x(a, b):
    """Rz(a) Rx(b), row-major."""
    ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
    return [[ca, -sa * cb, sa * sb], [sa, ca * cb, -ca * sb], [0.0, sb, cb]]


def mv(R, v):
    return [sum(R[r][c] * v[c] for c in range(3)) for r in range(3)]


def mtv(R, v):
    return [sum(R[c][r] * v[c] for c in range(3)) for r in range(3)]


def test_reference_node_carries_the_mapped_plate(sockdir):
    # MBDyn's `external structural mapping` with `reference node` (orientation matrix): the recorded
    # cantilever's mapped points carried by a reference node that translates and turns about z
    # (the plate stays level under the particles); its record x_r, R_r (column-major), v_r, w_r comes
    # first, the points relative to it in its frame. Closed forms: every vertex at x_r + R_r q~; the
    # answer's point loads R_r p~ add up to minus the particles' wall force, and its record is the
    # total in the reference frame, F0 = R_r^T F, M0 = R_r^T (moment about x_r of the wall contacts).
    rec = transcript()
    x0, R0 = [0.2, -0.1, 0.3], rot_z_x(0.1, 0.0)
    poses, rows, n = [], [], 0
    for seq, d, c, v in rec:
        if d == "mbdyn->peer" and c in (2, 6):
            q = [float(x) for x in v[:3 * M_POINTS]]
            qd = [float(x) for x in v[3 * M_POINTS:6 * M_POINTS]]
            xr, Rr = [x0[0] + 0.002 * n, x0[1] - 0.001 * n, x0[2]], rot_z_x(0.1 + 0.004 * n, 0.0)
            qt = sum((mtv(R0, [q[3 * j + a] - x0[a] for a in range(3)]) for j in range(M_POINTS)), [])
            qdt = sum((mtv(R0, qd[3 * j:3 * j + 3]) for j in range(M_POINTS)), [])
            vals = xr + [Rr[r][col] for col in range(3) for r in range(3)] + [0.1, -0.05, 0.0] + [0.0, 0.0, 0.2]
            rows.append((seq, d, c, [repr(x) for x in vals + qt + qdt]))
            poses.append((xr, Rr, qt))
            n += 1
        elif d == "peer->mbdyn" and c in (2, 6):
            rows.append((seq, d, c, ["0.0"] * (6 + 3 * M_POINTS)))
        else:
            rows.append((seq, d, c, v))
    steps = n - 1
    dump = f"fix D all mesh/dump 1 stl {sockdir}/mesh*.stl plate"
    answers = []
    _, loads, thermo, secs = couple(sockdir, steps, rows=rows, dump=dump, answers_out=answers,
                                    fix_extra="reference_node yes orientation matrix")
    assert answers[0][1:] == (7, [0x2 | 0x4 | (0x200 << 4), M_POINTS])  # flags: ref node, its matrix << 4
    tris = triangles()
    worst_v = worst_f = worst_f0 = worst_m0 = fscale = mscale = 0.0
    for k, (xr, Rr, qt) in enumerate(poses):
        pts = [[xr[a] + mv(Rr, qt[3 * j:3 * j + 3])[a] for a in range(3)] for j in range(M_POINTS)]
        mesh = read_stl(f"{sockdir}/mesh{k}.stl")
        worst_v = max(worst_v, max(abs(mesh[t][i][a] - pts[j][a]) for t, cs in enumerate(tris)
                                   for i, j in enumerate(cs) for a in range(3)))
        F0, M0, pt = loads[k][0:3], loads[k][3:6], loads[k][6:]
        p = [mv(Rr, pt[3 * j:3 * j + 3]) for j in range(M_POINTS)]
        F = [sum(p[j][a] for j in range(M_POINTS)) for a in range(3)]
        fp, fm, mr, r = thermo[k][0:3], thermo[k][3:6], thermo[k][6:9], thermo[k][9:12]
        m_origin = [mr[a] + cross(r, fm)[a] for a in range(3)]  # the wall contacts' moment about the origin
        m_ref = [m_origin[a] - cross(xr, fm)[a] for a in range(3)]
        fscale, mscale = max(fscale, max(map(abs, fp))), max(mscale, max(map(abs, m_ref)))
        worst_f = max(worst_f, max(abs(F[a] + fp[a]) for a in range(3)))
        worst_f0 = max(worst_f0, max(abs(mv(Rr, F0)[a] - fm[a]) for a in range(3)))
        worst_m0 = max(worst_m0, max(abs(mv(Rr, M0)[a] - m_ref[a]) for a in range(3)))
    print(f"mapping mesh, reference node: {steps + 1} exchanges in {secs:.1f} s; vertices vs x_r + R_r q~ "
          f"{worst_v:.1e} m; point loads + particles' wall force {worst_f / fscale:.1e} of {fscale:.3g} N; "
          f"record: F0 {worst_f0 / fscale:.1e}, M0 {worst_m0 / mscale:.1e} of {mscale:.3g} N m")
    assert fscale > 1.0  # the particles press on the plate
    assert worst_v <= 1e-15
    assert worst_f <= 1e-12 * fscale and worst_f0 <= 1e-12 * fscale and worst_m0 <= 1e-12 * mscale
