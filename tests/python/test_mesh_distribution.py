"""Distributed meshes (tests/decks/in.mesh_distribution): 200 spheres thrown into a static STL funnel
(fix mesh/surface/stress, 60 triangles) under a lid moved down by fix move/mesh, 500 steps, pairs and
mesh walls with tangential history (few steps: 4 ranks oversubscribe a 2-core machine).
* The funnel is split over 4 ranks (each keeps a part), the moving lid stays whole, and the atoms,
  the wall contacts with their history springs and the stress totals equal those of the replicated
  mesh ('distribute no') bit for bit (tolerance 0), on 1, 2 and 4 ranks.
* A restart written on 2 ranks with distributed meshes and read on 4 ranks equals the
  replicated run of the same steps in one process bit for bit.
* In one process: a mesh part of which lies outside the box is split on one rank; a mesh dump and a
  fix move/mesh defined after a run get the whole mesh back (read again from the file), with the same
  results as a mesh that was never split (spheres sliding on it keep their history across the change of
  local triangle ids); a bad 'distribute' value is refused.
"""
import os
import re
import shutil
import subprocess

import pytest

import dembridge
from dembridge import ROOT, new_lammps

HERE = os.path.dirname(os.path.abspath(__file__))
DECK = os.path.join(HERE, "..", "decks", "in.mesh_distribution")
WALLS = os.path.join(ROOT, "tests", "data", "liggghts-walls")
FILES = {"funnel.stl": os.path.join(WALLS, "mesh", "funnel.stl"), "plate.stl": os.path.join(WALLS, "mesh", "plate.stl"),
         "funnel200.data": os.path.join(WALLS, "hopper200_funnel_settle", "data.txt")}


def _lmp(wd, nprocs, dist, stage, out):
    cmd = [dembridge.lmp_executable(), "-in", "in.mesh_distribution", "-screen", "none", "-nocite", "-log", f"log.{out}",
           "-var", "plugin", str(dembridge.plugin_path()), "-var", "dist", dist, "-var", "stage", stage, "-var", "out", out]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    subprocess.run(cmd, cwd=wd, check=True, timeout=600)


def _stress_rows(log):
    """thermo rows: step and the six f_cad totals, as text (printed with %.17g)"""
    rows = []
    for line in open(log):
        t = line.split()
        if len(t) == 9 and t[0].isdigit():
            rows.append((t[0],) + tuple(t[3:]))
    return rows


def _split_line(log, mesh_id):
    m = re.search(rf"\(id {mesh_id}\): (all|part) of (\d+) triangles per rank \((\d+) to (\d+)\)", open(log).read())
    return m.group(1), int(m.group(2)), int(m.group(3)), int(m.group(4))


@pytest.fixture(scope="module")
def wd(tmp_path_factory):
    if not os.path.isfile(dembridge.plugin_path()):
        pytest.skip("plugin not built")
    d = tmp_path_factory.mktemp("mesh_distribution")
    shutil.copy(DECK, d)
    for name, src in FILES.items():
        shutil.copy(src, d / name)
    return d


def _same(wd, a, b):
    """atoms (sorted by id) as text and the wall contacts (rows gathered in rank order, so sorted), %.17g"""
    assert (wd / a).read_bytes() == (wd / b).read_bytes(), f"atoms of {a} != {b}"
    ca, cb = (open(wd / (r + ".walls")).read().split("ITEM: ENTRIES") for r in (a, b))
    assert ca[0] == cb[0] and sorted(ca[1].splitlines()) == sorted(cb[1].splitlines()), f"wall contacts of {a} != {b}"


@pytest.mark.two_cores
def test_distributed_equals_replicated_on_1_2_4_ranks(wd):
    _lmp(wd, 1, "no", "full", "no1")
    walls = open(wd / "no1.walls").read().split("ITEM: ENTRIES")[1].splitlines()[1:]
    meshes = {int(r.split()[1]) for r in walls if r.strip()}
    assert meshes == {1, 2}  # both the funnel and the lid touch particles at the end
    assert any(float(v) != 0.0 for row in _stress_rows(wd / "log.no1") for v in row[1:])
    for n in (1, 2, 4):
        _lmp(wd, n, "yes", "full", f"yes{n}")
        _same(wd, "no1", f"yes{n}")  # atoms and wall contacts (with history) do not depend on the split
    _lmp(wd, 4, "no", "full", "no4")
    # the totals are sums over ranks (round-off differs with the rank count): the same ranks sum the same forces
    assert _stress_rows(wd / "log.yes1") == _stress_rows(wd / "log.no1")
    assert _stress_rows(wd / "log.yes4") == _stress_rows(wd / "log.no4")
    kind, total, lo, hi = _split_line(wd / "log.yes4", "cad")
    assert kind == "part" and total == 60 and lo < 60 and hi <= 60
    assert _split_line(wd / "log.yes4", "lid") == ("all", 2, 2, 2)  # a moving mesh stays whole
    assert _split_line(wd / "log.no4", "cad") == ("all", 60, 60, 60)


@pytest.mark.two_cores
def test_restart_across_rank_counts(wd):
    _lmp(wd, 1, "no", "split", "split1")
    _lmp(wd, 2, "yes", "first", "first2")
    _lmp(wd, 4, "yes", "second", "second4")
    _same(wd, "split1", "second4")


BOX = ["units si", "atom_style sphere", "boundary f f f", "newton off", "comm_modify vel yes",
       "region box block -0.02 0.02 -0.02 0.02 -0.01 0.03 units box", "create_box 1 box",
       "lattice sc 0.004 origin 0.5 0.5 0.37475", "region bed block -0.016 0.016 -0.016 0.016 0.0014 0.0016 units box",
       "create_atoms 1 region bed", "set group all diameter 0.003 density 2500", "velocity all set 0.1 0.0 0.0 units box",
       "fix grav all gravity 9.81 vector 0 0 -1",
       "neighbor 0.001 bin", "neigh_modify delay 0", "timestep 1e-5",
       "fix m1 all property/global youngsModulus peratomtype 5.e7", "fix m2 all property/global poissonsRatio peratomtype 0.3",
       "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
       "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
       "pair_style gran model hertz tangential history", "pair_coeff * *", "fix integr all nve/sphere"]


def _write_plate(path, n=20, half=0.1):
    """an n x n grid of squares, two triangles each, over [-half, half]^2 at z = 0 (ASCII STL)"""
    h = 2 * half / n
    with open(path, "w") as f:
        f.write("solid plate\n")
        for i in range(n):
            for j in range(n):
                x0, y0 = -half + i * h, -half + j * h
                p = [(x0, y0), (x0 + h, y0), (x0 + h, y0 + h), (x0, y0 + h)]
                for tri in ((p[0], p[1], p[2]), (p[0], p[2], p[3])):
                    f.write("facet normal 0 0 1\nouter loop\n")
                    for x, y in tri:
                        f.write(f"vertex {x!r} {y!r} 0.0\n")
                    f.write("endloop\nendfacet\n")
        f.write("endsolid plate\n")


def _one_rank(wd, dist, later):
    """800 triangles over 0.2 m x 0.2 m in a 0.04 m box: one rank keeps only what its atoms can reach"""
    _write_plate(wd / "plate.stl")
    lmp = new_lammps(log=str(wd / "log.lammps"))
    os.chdir(wd)
    for line in BOX + [f"fix cad all mesh/surface/stress file plate.stl type 1 distribute {dist}",
                       "fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes cad",
                       "run 300"] + later + ["run 300"]:
        lmp.command(line)
    x, v = lmp.numpy.extract_atom("x").tolist(), lmp.numpy.extract_atom("v").tolist()
    xs = sorted(zip(lmp.numpy.extract_atom("id").tolist(), map(tuple, x), map(tuple, v)))
    f = [lmp.extract_fix("cad", 0, 1, k) for k in range(6)]
    lmp.close()
    return xs, f, re.findall(r"\(id cad\): (all|part) of 800 triangles per rank \((\d+) to", open(wd / "log.lammps").read())


@pytest.mark.parametrize("later", [["dump d all mesh/stl 300 plate*.stl"],
                                   ["fix mv all move/mesh mesh cad linear -0.05 0.0 0.0"]], ids=["dump", "move"])
def test_whole_again_after_a_split_run(tmp_path, later):
    os.makedirs(tmp_path / "yes")
    os.makedirs(tmp_path / "no")
    cwd = os.getcwd()
    try:
        xs, fs, split = _one_rank(tmp_path / "yes", "yes", later)
        xr, fr, whole = _one_rank(tmp_path / "no", "no", later)
    finally:
        os.chdir(cwd)
    assert split[0][0] == "part" and int(split[0][1]) < 400 and split[-1] == ("all", "800")
    assert all(w == ("all", "800") for w in whole)
    assert xs == xr and fs == fr
    assert fs[2] < 0.0  # the spheres slide on the plate (tangential history across the two runs) and load it
    if "dump" in later[0]:
        assert (tmp_path / "yes" / "plate600.stl").read_bytes() == (tmp_path / "no" / "plate600.stl").read_bytes()


def test_bad_distribute_value(tmp_path):
    shutil.copy(FILES["plate.stl"], tmp_path / "plate.stl")
    lmp = new_lammps()
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for line in BOX:
            lmp.command(line)
        with pytest.raises(Exception, match=r"fix mesh/surface.*distribute.*yes.*no"):
            lmp.command("fix cad all mesh/surface file plate.stl type 1 distribute maybe")
    finally:
        os.chdir(cwd)
        lmp.close()
