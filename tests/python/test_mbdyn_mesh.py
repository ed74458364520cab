"""Acceptance C of issue 11: `fix mbdyn ... node mesh MESH-ID`. A square STL plate (fix
mesh/surface/stress, reference point off the MBDyn point) follows the test peer's tilted, spinning
node; particles fall onto it (fix wall/gran mesh). At every step, serial and on 2 ranks: the loads
sent equal the mesh's force, and its moment moved from the reference point to MBDyn's point, to
<= 1e-12 relative, and the force sent is minus the particles' total force (pair forces cancel);
the point attached to the mesh at t0 and the mesh's reference point are where
the node's pose (from the test peer's log of the kinematics it sent) puts them, to <= 1e-12."""
import os
import shutil
import tempfile

import pytest

from dembridge import plugin_path
from gran_deck import GRAN_HEAD, HOOKE_ONE_TYPE
from test_fix_mbdyn import PEER, Peer, parse_thermo, run_lammps

pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")

X0 = (0.0, 0.0, 0.1)
REF = (0.05, 0.02, 0.1)
STL = """solid plate
facet normal 0 0 1
 outer loop
  vertex -0.2 -0.2 0.1
  vertex 0.2 -0.2 0.1
  vertex 0.2 0.2 0.1
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex -0.2 -0.2 0.1
  vertex 0.2 0.2 0.1
  vertex -0.2 0.2 0.1
 endloop
endfacet
endsolid plate
"""


def deck(sock, steps, procs=""):
    return f"""{GRAN_HEAD}
{procs}
region box block -0.5 0.5 -0.5 0.5 -0.3 0.5 units box
create_box 1 box
region cloud block -0.15 0.15 -0.15 0.15 0.14 0.3 units box
create_atoms 1 random 40 12345 cloud overlap 0.07 maxtry 500
set type 1 diameter 0.06
set type 1 density 1000
velocity all set 0 0 -3 units box
{HOOKE_ONE_TYPE}
neighbor 0.01 bin
timestep 1e-4
fix plate all mesh/surface/stress file plate.stl type 1 reference_point {REF[0]} {REF[1]} {REF[2]}
fix walls all wall/gran model hooke tangential history mesh n_meshes 1 meshes plate
fix I all nve/sphere
fix M all mbdyn path {sock} node mesh plate orientation matrix connect_timeout 60 io_timeout 60
compute ff all reduce sum fx fy fz
thermo_style custom step f_M[1][1] f_M[1][2] f_M[1][3] f_M[1][4] f_M[1][5] f_M[1][6] &
  f_plate[1] f_plate[2] f_plate[3] f_plate[4] f_plate[5] f_plate[6] f_plate[7] f_plate[8] f_plate[9] &
  f_M[5] f_M[6] f_M[7] c_ff[1] c_ff[2] c_ff[3]
thermo_modify format float %.17g
thermo 1
run {steps}
"""


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


@pytest.fixture
def sockdir():
    d = tempfile.mkdtemp(prefix="mbm", dir="/tmp")
    yield d
    shutil.rmtree(d, ignore_errors=True)


def run_mesh(sockdir, nprocs, steps=300):
    open(os.path.join(sockdir, "plate.stl"), "w").write(STL)
    sock = os.path.join(sockdir, "m.sock")
    klog = os.path.join(sockdir, f"kin{nprocs}.txt")
    peer = Peer(sock, "--nodes", "1", "--orientation", "matrix", "--steps", str(steps), "--dt", "1e-4",
                "--mass", "5", "--inertia", "0.05", "--x0", ",".join(map(str, X0)), "--v0", "0,0,0",
                "--kinematics-log", klog, timeout=120)
    rc, out, _ = run_lammps(deck(sock, steps, "processors 2 1 1" if nprocs == 2 else ""), sockdir, nprocs=nprocs,
                            timeout=300)
    prc, pout = peer.finish(timeout=120)
    assert rc == 0, out[-3000:]
    assert prc == 0, pout
    kin = [[float(v) for v in l.split()] for l in open(klog)]
    return parse_thermo(out, 22), kin


@pytest.mark.two_cores
def test_mesh_follows_node_and_loads_are_the_mesh_force_and_moment(sockdir):
    results = {}
    for nprocs in (1, 2):
        thermo, kin = run_mesh(sockdir, nprocs)
        results[nprocs] = thermo
        x0, R0 = kin[0][2:5], kin[0][5:14]
        ref0 = [REF[c] - x0[c] for c in range(3)]
        body_ref = [sum(R0[3 * r + c] * ref0[r] for r in range(3)) for c in range(3)]  # R0^T (ref - x0)
        worst_load = worst_pose = worst_third = 0.0
        hits = 0
        fmax = max(max(abs(v) for v in row[6:9]) for row in thermo.values())
        for step, row in thermo.items():
            if step == 0:
                continue
            F, M, Fm, Mm, ref, tracked, fp = row[0:3], row[3:6], row[6:9], row[9:12], row[12:15], row[15:18], row[18:21]
            x, R = kin[step][2:5], kin[step][5:14]   # loose, N = 1: LAMMPS step n holds message n
            # the mesh pose: the point attached at t0 and the stress reference point
            expect_ref = [x[c] + sum(R[3 * c + k] * body_ref[k] for k in range(3)) for c in range(3)]
            worst_pose = max(worst_pose, max(abs(tracked[c] - x[c]) for c in range(3)),
                             max(abs(ref[c] - expect_ref[c]) for c in range(3)))
            # the loads: the mesh's force, its moment about the reference point moved to the point
            arm = [ref[c] - x[c] for c in range(3)]
            M_about_point = [Mm[c] + cross(arm, Fm)[c] for c in range(3)]
            dev = max(max(abs(F[c] - Fm[c]) for c in range(3)), max(abs(M[c] - M_about_point[c]) for c in range(3)))
            worst_load = max(worst_load, dev / fmax)
            # independent of the mesh fix: the pair forces cancel, so the particles' total force is
            # minus the force of the wall contacts on the mesh (Newton's third law)
            worst_third = max(worst_third, max(abs(F[c] + fp[c]) for c in range(3)) / fmax)
            if max(abs(v) for v in Fm) > 1e-6 * fmax:
                hits += 1
        print(f"node mesh, {nprocs} rank(s): {hits} steps with wall contacts, max |F| {fmax:.3e}; loads vs mesh "
              f"force/moment about the point {worst_load:.2e} relative; force sent + particles' total force "
              f"{worst_third:.2e}; mesh pose vs node {worst_pose:.2e}")
        assert hits >= 20, "the particles never touched the mesh: the test checks nothing"
        assert worst_load <= 1e-12
        assert worst_pose <= 1e-12
        assert worst_third <= 1e-12
    s, p = results[1], results[2]
    dev = max(abs(a - b) for step in s for a, b in zip(s[step][0:6], p[step][0:6])) / fmax
    print(f"serial vs 2 ranks, loads: {dev:.2e} relative")
    assert dev <= 1e-8


def test_mesh_tight_coupling_loads_are_the_last_trial_evaluation(sockdir):
    """Tight: each MBDyn iterate moves the mesh and re-evaluates the wall contacts (the mesh's
    force totals start again from zero); the loads sent with the converged answer are the mesh's
    force and moment of that last evaluation, about the point where the mesh is."""
    open(os.path.join(sockdir, "plate.stl"), "w").write(STL)
    sock = os.path.join(sockdir, "t.sock")
    peer = Peer(sock, "--nodes", "1", "--orientation", "matrix", "--coupling", "tight", "--steps", "300",
                "--dt", "1e-4", "--mass", "5", "--inertia", "0.05", "--x0", ",".join(map(str, X0)), "--v0", "0,0,0",
                "--force", "0,0,1", timeout=120)
    d = deck(sock, 300).replace("orientation matrix", "orientation matrix coupling tight tolerance 1e-12 max_iterations 8")
    d = d.replace("f_M[5] f_M[6] f_M[7]", "f_M[5] f_M[6] f_M[7] f_M[2]")
    rc, out, _ = run_lammps(d, sockdir, timeout=300)
    prc, pout = peer.finish(timeout=120)
    assert rc == 0, out[-3000:]
    assert prc == 0, pout
    thermo = parse_thermo(out, 23)
    fmax = max(max(abs(v) for v in row[6:9]) for row in thermo.values())
    worst, iterated = 0.0, 0
    for step, row in thermo.items():
        if step == 0:
            continue
        F, M, Fm, Mm, ref, x, fp = row[0:3], row[3:6], row[6:9], row[9:12], row[12:15], row[15:18], row[19:22]
        arm = [ref[c] - x[c] for c in range(3)]
        Mp = [Mm[c] + cross(arm, Fm)[c] for c in range(3)]
        worst = max(worst, max(abs(F[c] - Fm[c]) for c in range(3)) / fmax,
                    max(abs(M[c] - Mp[c]) for c in range(3)) / fmax, max(abs(F[c] + fp[c]) for c in range(3)) / fmax)
        iterated += row[18] > 1
    print(f"node mesh, tight: {iterated} of 300 steps iterated; loads vs mesh force/moment and vs the particles' "
          f"total force {worst:.2e} relative ({pout.strip()})")
    assert iterated > 100
    assert worst <= 1e-12
