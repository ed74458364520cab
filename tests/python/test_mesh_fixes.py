"""fix mesh/surface(/stress), fix move/mesh and fix mesh/dump through LAMMPS: placement and motion
bit for bit against the walls oracle's independent Python model (tests/data/liggghts-walls/mesh),
the mesh-triggered re-neighbouring, the stress vector, restart, and bad input."""
import math
import os
import re
import struct

import pytest

from dembridge import ROOT, new_lammps

DATA = os.path.join(ROOT, "tests", "data", "liggghts-walls", "mesh")


def deck_head(ntypes=1, skin=0.001, box=0.06, periodic=False):
    b = "p p p" if periodic else "f f f"
    return [
        "units si", "atom_style sphere", f"boundary {b}", "newton off", "comm_modify vel yes",
        f"region box block -{box} {box} -{box} {box} -{box} {box}", f"create_box {ntypes} box",
        "create_atoms 1 single 0.0 0.0 0.05 units box", "set group all diameter 0.004 density 2500",
        f"neighbor {skin} bin", "neigh_modify delay 0", "timestep 1e-6", "fix integr all nve/sphere",
    ]


def run(lines, log=None):
    lmp = new_lammps(log=log)
    try:
        for line in lines:
            lmp.command(line)
    except Exception:
        lmp.close()
        raise
    return lmp


def error_of(lines):
    try:
        run(lines).close()
    except Exception as e:  # noqa: BLE001 - the lammps module raises Exception with the ERROR text
        return str(e)
    return None


def read_stl_nodes(path):
    out = []
    for line in open(path):
        t = line.split()
        if t and t[0] == "vertex":
            out.append(tuple(float(c) for c in t[1:4]))
    return out


def read_vtk_point_velocities(path):
    lines = open(path).read().split("\n")
    i = lines.index("VECTORS velocity double")
    n = int(lines[i - 1].split()[1])
    return [tuple(float(c) for c in l.split()) for l in lines[i + 1:i + 1 + n]]


def ref_lines(name):
    return [l.split() for l in open(os.path.join(DATA, name)) if l.strip() and not l.startswith("#")]


def ref_motion_state(block, step):
    """nodes and node velocities per triangle from motion.ref (hex floats of the Python model)"""
    out, on = {}, False
    for t in ref_lines("motion.ref"):
        if t[0] in ("rotate", "stacked"):
            on = t[0] == block and int(t[2]) == step
        elif on and t[0] == "state":
            v = [float.fromhex(c) for c in t[2:]]
            out[int(t[1])] = (v[0:9], v[21:30])
    return out


def flat_nodes(nodes):
    return [c for p in nodes for c in p]


def test_placement_through_lammps_is_bit_identical(tmp_path):
    out = tmp_path / "placed.stl"
    lmp = run(deck_head() + [
        f"fix cad all mesh/surface file {DATA}/plate.stl type 1 scale 0.8 rotate axis 1.0 0.0 0.0 angle 20.0 move 0.0 0.0 0.003",
        f"fix d all mesh/dump 1 stl {out} cad", "run 0"])
    lmp.close()
    want = []
    for t in ref_lines("plate_placed.ref"):
        if t[0] == "tri" and t[2] == "nodes":
            want += [float.fromhex(c) for c in t[3:12]]
    assert flat_nodes(read_stl_nodes(out)) == want


def test_linear_motion_is_incremental(tmp_path):
    out = tmp_path / "m.stl"
    lmp = run(deck_head() + [
        f"fix cad all mesh/surface file {DATA}/pusher.stl type 1",
        "fix mv all move/mesh mesh cad linear 0.1 -0.2 0.05",
        f"fix d all mesh/dump 100 stl {out} cad", "run 100"])
    lmp.close()
    p0 = read_stl_nodes(os.path.join(DATA, "pusher.stl"))
    dx = (0.1 * 1e-6, -0.2 * 1e-6, 0.05 * 1e-6)
    want = []
    for p in p0:
        q = list(p)
        for _ in range(100):
            q = [q[k] + dx[k] for k in range(3)]
        want += q
    assert flat_nodes(read_stl_nodes(out)) == want


def test_rotate_nodes_and_velocities_match_the_model(tmp_path):
    out = tmp_path / "r_*.vtk"
    stl = tmp_path / "r.stl"
    lmp = run(deck_head() + [
        f"fix cad all mesh/surface file {DATA}/paddle.stl type 1",
        "fix rot all move/mesh mesh cad rotate origin 0.0 0.0 0.0 axis 0.0 0.0 1.0 period 0.2",
        f"fix d all mesh/dump 600 vtk {out} cad", f"fix s all mesh/dump 600 stl {stl} cad", "run 600"])
    lmp.close()
    ref = ref_motion_state("rotate", 600)
    nodes = flat_nodes(read_stl_nodes(stl))
    vel = flat_nodes(read_vtk_point_velocities(tmp_path / "r_600.vtk"))
    for t, (n, v) in ref.items():
        assert nodes[9 * t:9 * t + 9] == n
        assert vel[9 * t:9 * t + 9] == v


def test_stacked_movers_superpose_in_fix_order(tmp_path):
    stl = tmp_path / "s.stl"
    vtk = tmp_path / "s.vtk"
    lmp = run(deck_head() + [
        f"fix cad all mesh/surface file {DATA}/paddle.stl type 1",
        "fix lin all move/mesh mesh cad linear 0.1 -0.05 0.02",
        "fix rot all move/mesh mesh cad rotate origin 0.001 0.002 0.0 axis 0.3 0.4 1.0 period 0.05",
        f"fix s all mesh/dump 300 stl {stl} cad", f"fix v all mesh/dump 300 vtk {vtk} cad", "run 300"])
    lmp.close()
    nodes = flat_nodes(read_stl_nodes(stl))
    vel = flat_nodes(read_vtk_point_velocities(vtk))
    for t, (n, v) in ref_motion_state("stacked", 300).items():
        assert nodes[9 * t:9 * t + 9] == n
        assert vel[9 * t:9 * t + 9] == v


def neighbor_builds(log):
    m = re.findall(r"Neighbor list builds = (\d+)", open(log).read())
    return int(m[-1])


def test_moving_mesh_triggers_reneighbouring_one_step_later(tmp_path):
    """One particle at rest far from the paddle: every build comes from the mesh trigger (a node
    moved more than skin/2 since the last build -> rebuild on the next step, spec §6)."""
    log = tmp_path / "log.lammps"
    nsteps = 4000
    lmp = run(deck_head() + [
        f"fix cad all mesh/surface file {DATA}/paddle.stl type 1",
        "fix rot all move/mesh mesh cad rotate origin 0.0 0.0 0.0 axis 0.0 0.0 1.0 period 0.2", f"run {nsteps}"],
        log=str(log))
    lmp.close()
    # the same schedule from the closed-form rotation of the paddle's nodes
    nodes = read_stl_nodes(os.path.join(DATA, "paddle.stl"))
    w = 2 * math.pi / 0.2
    trig = 0.25 * 0.001 ** 2
    last, builds, force_at = 0, 0, None
    for s in range(1, nsteps + 1):
        if force_at == s:
            builds += 1
            last = s
            force_at = None
            continue
        a, b = w * s * 1e-6, w * last * 1e-6
        d2 = max((x * math.cos(a) - y * math.sin(a) - (x * math.cos(b) - y * math.sin(b))) ** 2 +
                 (x * math.sin(a) + y * math.cos(a) - (x * math.sin(b) + y * math.cos(b))) ** 2 for x, y, _ in nodes)
        if d2 > trig:
            force_at = s + 1
    assert builds >= 6
    assert neighbor_builds(log) == builds


def test_stress_vector_reports_reference_point_that_moves_with_the_mesh():
    lmp = run(deck_head() + [
        f"fix cad all mesh/surface/stress file {DATA}/plate.stl type 1 reference_point 0.01 0.0 0.0",
        "fix mv all move/mesh mesh cad linear 0.0 0.0 1.0",
        "thermo_style custom step f_cad[1] f_cad[4] f_cad[7] f_cad[9]", "run 10"])
    assert lmp.extract_fix("cad", 0, 1, 6) == 0.01
    assert lmp.extract_fix("cad", 0, 1, 8) == pytest.approx(1e-5, rel=1e-12)
    assert lmp.extract_fix("cad", 0, 1, 0) == 0.0  # no wall fix: no force
    lmp.close()


def test_restart_continues_the_mesh_motion_bitwise(tmp_path):
    movers = ["fix rot all move/mesh mesh cad rotate origin 0.001 0.0 0.0 axis 0.2 0.1 1.0 period 0.05",
              "fix wig all move/mesh mesh cad wiggle amplitude 0.002 0.0 0.001 period 0.003"]
    head = deck_head() + [f"fix cad all mesh/surface/stress file {DATA}/paddle.stl type 1 reference_point 0.0 0.01 0.0"] + movers
    split = tmp_path / "split_*.vtk"
    lmp = run(head + ["run 300", f"write_restart {tmp_path}/r.restart", f"fix d all mesh/dump 300 vtk {split} cad", "run 300"])
    ref_split = lmp.extract_fix("cad", 0, 1, 7)
    lmp.close()
    rest = tmp_path / "rest_*.vtk"
    lmp = run(["atom_style sphere", f"read_restart {tmp_path}/r.restart", "neighbor 0.001 bin", "neigh_modify delay 0",
               "timestep 1e-6", "fix integr all nve/sphere",
               f"fix cad all mesh/surface/stress file {DATA}/paddle.stl type 1 reference_point 0.0 0.01 0.0"] + movers +
              [f"fix d all mesh/dump 300 vtk {rest} cad", "run 300"])
    assert lmp.extract_fix("cad", 0, 1, 7) == ref_split
    lmp.close()
    for step in (300, 600):
        a = open(tmp_path / f"split_{step}.vtk").read()
        b = open(tmp_path / f"rest_{step}.vtk").read()
        assert a == b, f"mesh differs at step {step}"


def bad_stl(tmp_path, name, body):
    p = tmp_path / name
    p.write_text(body)
    return p


FACET = "facet normal 0 0 1\n outer loop\n  vertex {}\n  vertex {}\n  vertex {}\n endloop\nendfacet\n"


def test_bad_input_gives_errors_naming_command_and_argument(tmp_path):
    nan = bad_stl(tmp_path, "nan.stl", "solid a\n" + FACET.format("0 0 0", "nan 0 0", "0 0.01 0") + "endsolid a\n")
    deg = bad_stl(tmp_path, "deg.stl", "solid a\n" + FACET.format("0 0 0", "0.01 0 0", "0.02 0 0") + "endsolid a\n")
    mal = bad_stl(tmp_path, "mal.stl", "solid a\n" + FACET.format("0 0 0", "0.01 0 zero", "0 0.01 0") + "endsolid a\n")
    far = bad_stl(tmp_path, "far.stl", "solid a\n" + FACET.format("1 1 1", "1.01 1 1", "1 1.01 1") + "endsolid a\n")
    plate = f"{DATA}/plate.stl"
    head = deck_head()
    cases = {
        "missing file": (f"fix cad all mesh/surface file {tmp_path}/none.stl type 1",
                         ["fix mesh/surface (id cad) file", "cannot open STL file"]),
        "malformed": (f"fix cad all mesh/surface file {mal} type 1", ["line 5", "'zero' is not a number"]),
        "nan": (f"fix cad all mesh/surface file {nan} type 1", ["triangle 1 (file order) has a non-finite"]),
        "degenerate": (f"fix cad all mesh/surface file {deg} type 1", ["triangle 1 (file order) is degenerate"]),
        "type range": (f"fix cad all mesh/surface file {plate} type 3", ["(id cad)", "type 3 is outside 1..1"]),
        "type before file": (f"fix cad all mesh/surface type 1 file {plate}", ["'type'", "expected keyword 'file'"]),
        "curvature": (f"fix cad all mesh/surface file {plate} type 1 curvature 70", ["curvature", "0 < curvature < 60"]),
        "unknown keyword": (f"fix cad all mesh/surface file {plate} type 1 colour red", ["colour", "unknown keyword"]),
        "scale not number": (f"fix cad all mesh/surface file {plate} type 1 scale big", ["scale", "'big'"]),
        "zero axis": (f"fix cad all mesh/surface file {plate} type 1 rotate axis 0 0 0 angle 5", ["rotate axis", "non-zero"]),
        "rotate order": (f"fix cad all mesh/surface file {plate} type 1 rotate angle 5 axis 0 0 1", ["'angle'", "expected keyword 'axis'"]),
        "reference_point on plain mesh": (f"fix cad all mesh/surface file {plate} type 1 reference_point 0 0 0",
                                          ["reference_point", "mesh/surface/stress"]),
        "wear model": (f"fix cad all mesh/surface/stress file {plate} type 1 wear archard", ["wear", "expected 'finnie' or 'off'", "'archard'"]),
        "heal value": (f"fix cad all mesh/surface file {plate} type 1 heal yes", ["heal", "auto_remove_duplicates"]),
        "missing value": (f"fix cad all mesh/surface file {plate} type 1 move 0 0", ["move", "missing value"]),
    }
    for name, (line, needles) in cases.items():
        msg = error_of(head + [line])
        assert msg is not None, name
        for n in needles:
            assert n in msg, f"{name}: '{n}' not in: {msg}"
    mesh = f"fix cad all mesh/surface file {plate} type 1"
    movers = {
        "unknown mesh": ("fix mv all move/mesh mesh nope linear 1 0 0", ["fix move/mesh (id mv)", "mesh ID 'nope' does not exist"]),
        "not a mesh": ("fix mv all move/mesh mesh integr linear 1 0 0", ["'integr' is a fix nve/sphere, not a mesh"]),
        "unknown motion": ("fix mv all move/mesh mesh cad spin 1 0 0", ["'spin'", "unknown motion"]),
        "missing mesh keyword": ("fix mv all move/mesh cad linear 1 0 0", ["'cad'", "expected keyword 'mesh'"]),
        "extra argument": ("fix mv all move/mesh mesh cad linear 1 0 0 7", ["'7'", "unexpected argument"]),
        "rotate keyword": ("fix mv all move/mesh mesh cad rotate origin 0 0 0 axis 0 0 1 omega 3",
                           ["'omega'", "expected keyword 'period'"]),
        "viblin order": ("fix mv all move/mesh mesh cad viblin axis 0 0 1 order 0 amplitude phase period", ["order", "1 <= order <= 30"]),
        "variable style": ("fix mv all move/mesh mesh cad linear/variable 1 0 0", ["linear/variable velocity 1", "v_name"]),
        "dump format": (f"fix d all mesh/dump 10 ply {tmp_path}/x cad", ["format 'ply'", "vtk or stl"]),
        "dump mesh": (f"fix d all mesh/dump 10 vtk {tmp_path}/x nope", ["fix mesh/dump (id d)", "'nope' does not exist"]),
    }
    for name, (line, needles) in movers.items():
        msg = error_of(head + [mesh, line])
        assert msg is not None, name
        for n in needles:
            assert n in msg, f"{name}: '{n}' not in: {msg}"
    run_errors = {
        "undefined variable": ([mesh, "fix mv all move/mesh mesh cad linear/variable v_a v_b v_c", "run 1"],
                               ["variable 'a' does not exist"]),
        "conveyor with mover": ([f"fix cad all mesh/surface file {plate} type 1 surface_vel 1 0 0",
                                 "fix mv all move/mesh mesh cad linear 1 0 0", "run 1"], ["surface_vel", "move/mesh"]),
        "mesh outside box": ([f"fix cad all mesh/surface file {far} type 1", "run 1"],
                             ["all 1 mesh elements are outside the simulation box"]),
    }
    for name, (lines, needles) in run_errors.items():
        msg = error_of(head + lines)
        assert msg is not None, name
        for n in needles:
            assert n in msg, f"{name}: '{n}' not in: {msg}"


def test_linear_variable_and_rotate_variable_follow_their_variables(tmp_path):
    stl = tmp_path / "v.stl"
    stl_ref = tmp_path / "c.stl"
    common = deck_head() + [f"fix cad all mesh/surface file {DATA}/paddle.stl type 1"]
    lmp = run(common + ["variable vx equal 0.2", "variable vy equal 0.0", "variable vz equal -0.1", "variable w equal 12.0",
                        "fix a all move/mesh mesh cad linear/variable v_vx v_vy v_vz",
                        "fix b all move/mesh mesh cad rotate/variable origin 0 0 0 axis 0 0 1 omega v_w",
                        f"fix d all mesh/dump 50 stl {stl} cad", "run 50"])
    lmp.close()
    lmp = run(common + ["fix a all move/mesh mesh cad linear 0.2 0.0 -0.1",
                        f"fix b all move/mesh mesh cad rotate origin 0 0 0 axis 0 0 1 period {2 * math.pi / 12.0!r}",
                        f"fix d all mesh/dump 50 stl {stl_ref} cad", "run 50"])
    lmp.close()
    a, b = read_stl_nodes(stl), read_stl_nodes(stl_ref)
    assert max(abs(x - y) for p, q in zip(a, b) for x, y in zip(p, q)) < 1e-15
    assert a != read_stl_nodes(os.path.join(DATA, "paddle.stl"))


def test_stress_vector_in_thermo_variables_and_ave_time_carries_the_weight():
    """A sphere resting on the plate: the force on the mesh from fix ave/time, a variable and
    thermo equals its weight (closed form m g), the torque about the reference point is r x F."""
    lines = ["units si", "atom_style sphere", "boundary f f f", "newton off", "comm_modify vel yes",
             "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05", "create_box 1 box",
             "create_atoms 1 single 0.004 -0.003 0.005 units box", "set group all diameter 0.01 density 2500",
             "neighbor 0.001 bin", "neigh_modify delay 0", "timestep 1e-6",
             "fix m1 all property/global youngsModulus peratomtype 5.e7",
             "fix m2 all property/global poissonsRatio peratomtype 0.3",
             "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3",
             "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
             "pair_style gran model hertz tangential history", "pair_coeff * *",
             f"fix cad all mesh/surface/stress file {DATA}/plate.stl type 1 reference_point 0.01 0.0 0.0",
             "fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes cad",
             "fix integr all nve/sphere", "fix grav all gravity 9.81 vector 0 0 -1",
             "variable fz equal f_cad[3]", "variable ty equal f_cad[5]",
             "fix avg all ave/time 1 1000 1000 f_cad[3] v_fz f_cad[5]",
             "thermo_style custom step f_cad[3] v_fz f_avg[1]", "run 30000"]
    lmp = run(lines)
    m = 2500 * 4.0 / 3.0 * math.pi * 0.005 ** 3
    weight = m * 9.81
    fz_avg = lmp.extract_fix("avg", 0, 1, 0)
    assert fz_avg == pytest.approx(-weight, rel=2e-3)           # F on the mesh = -(m g) up to the residual bounce
    assert lmp.extract_fix("avg", 0, 1, 1) == fz_avg            # the variable is the same number
    assert lmp.extract_variable("fz") == lmp.extract_fix("cad", 0, 1, 2)
    # torque about p = (0.01, 0, 0) of a vertical force F_z at (x, y, 0): t_y = -(x - 0.01) F_z
    x = lmp.numpy.extract_atom("x")[0]
    assert lmp.extract_fix("cad", 0, 1, 4) == pytest.approx(-(x[0] - 0.01) * lmp.extract_fix("cad", 0, 1, 2), rel=1e-6, abs=1e-12)
    lmp.close()


def test_move_mesh_does_not_claim_to_integrate_the_atoms(tmp_path):
    """fix move/mesh moves triangles, not atoms: LAMMPS must not warn that the group's atoms are
    'time integrated more than once' beside fix nve/sphere (LIGGGHTS decks give it group all)"""
    log = tmp_path / "log.lammps"
    lmp = run(deck_head() + [
        f"fix cad all mesh/surface file {DATA}/pusher.stl type 1",
        "fix mv all move/mesh mesh cad linear 0.1 -0.2 0.05", "run 10"], log=str(log))
    lmp.close()
    text = log.read_text()
    assert "Loop time" in text
    assert "time integrated more than once" not in text


def test_stl_file_errors_name_the_file_and_what_was_expected(tmp_path):
    """A truncated binary STL, a folder, a 4th number on a vertex line and coordinates too large
    for double arithmetic: each an ERROR of fix mesh/surface naming the file and the problem."""
    plate = open(f"{DATA}/plate.stl").read()
    binary = bytearray(80) + (2).to_bytes(4, "little")
    for tri in ((-0.02, -0.02, 0, 0.02, -0.02, 0, 0.02, 0.02, 0), (-0.02, -0.02, 0, 0.02, 0.02, 0, -0.02, 0.02, 0)):
        binary += struct.pack("<12fH", 0, 0, 1, *tri, 0)
    cut = tmp_path / "cut.stl"
    cut.write_bytes(bytes(binary[:-30]))
    extra = bad_stl(tmp_path, "extra.stl", plate.replace("vertex 0.02 -0.02 0.0", "vertex 0.02 -0.02 0.0 1.0", 1))
    huge = bad_stl(tmp_path, "huge.stl", "solid a\n" + FACET.format("0 0 0", "1e300 0 0", "0 1e300 0") + "endsolid a\n")
    cases = {
        "truncated binary": (cut, [f"file '{cut}': binary STL file '{cut}' (154 bytes)", "the header gives 2 facets",
                                   "the file ends inside facet 2"]),
        "folder": (tmp_path, [f"STL file '{tmp_path}' is a directory, expected an STL file"]),
        "4th number": (extra, [f"malformed ASCII STL file '{extra}' line", "'1.0' after the 3 coordinates of a vertex"]),
        "1e300": (huge, ["triangle 1 (file order): the length of edge 1 overflows double precision (coordinates up to 1e+300)"]),
    }
    for name, (path, needles) in cases.items():
        msg = error_of(deck_head() + [f"fix cad all mesh/surface file {path} type 1"])
        assert msg is not None, name
        for n in ["fix mesh/surface (id cad)"] + needles:
            assert n in msg, f"{name}: '{n}' not in: {msg}"
