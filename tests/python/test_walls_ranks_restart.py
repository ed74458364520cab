"""Walls across ranks and restarts (issue 10, acceptances D and E) with tests/decks/in.walls_paddle_bed:
1968 spheres in a cylinder (primitive zplane + zcylinder walls) stirred by an STL paddle rotating
with fix move/mesh, pairs + walls with tangential and epsd rolling history, 1000 steps.
* E: 1, 2 and 4 ranks agree bit for bit (tolerance 0) in x, v, omega and
  in the per-contact wall output (compute wall/gran/local: forces and the history springs).
* D: 500 steps + write_restart + a new process that reads it and runs 500 steps equals
  `run 500` + `run 500` in one process bitwise: positions, velocities, spins, forces, the wall
  contacts with their history, and the mesh pose (the paddle's closest points to the particles).
"""
import os
import shutil
import subprocess

import numpy as np
import pytest

import dembridge

HERE = os.path.dirname(os.path.abspath(__file__))
DECK = os.path.join(HERE, "..", "decks", "in.walls_paddle_bed")
STL = os.path.join(HERE, "..", "data", "liggghts-walls", "mesh_move_rotate_paddle", "paddle.stl")


def _lmp(workdir, nprocs=1, **var):
    cmd = [dembridge.lmp_executable(), "-in", "in.walls_paddle_bed", "-screen", "none", "-nocite", "-log",
           f"log.{var.get('stage', 'full')}.{nprocs}", "-var", "plugin", str(dembridge.plugin_path())]
    for k, v in var.items():
        cmd += ["-var", k, str(v)]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    subprocess.run(cmd, cwd=workdir, check=True, timeout=900)


def _atoms(path):
    rows = [l.split() for l in open(path).read().split("ITEM: ATOMS")[1].splitlines()[1:] if l.strip()]
    a = np.array(rows, dtype=float)
    return a[np.argsort(a[:, 0])]


def _contacts(path):
    rows = [l.split() for l in open(path).read().split("ITEM: ENTRIES")[1].splitlines()[1:] if l.strip()]
    a = np.array(rows, dtype=float)
    return a[np.lexsort((a[:, 2], a[:, 1], a[:, 0]))]


@pytest.fixture(scope="module")
def bed(tmp_path_factory):
    if not os.path.isfile(dembridge.plugin_path()):
        pytest.skip("plugin not built")
    wd = tmp_path_factory.mktemp("paddle_bed")
    shutil.copy(DECK, wd)
    shutil.copy(STL, wd)
    _lmp(wd, stage="data")
    return wd


def _rel(a, b):
    d = np.linalg.norm(a - b, axis=1)
    n = np.linalg.norm(b, axis=1)
    return float(np.max(d / np.maximum(n, 1e-6 * n.max())))


@pytest.mark.two_cores
def test_ranks_agree(bed):
    for n in (1, 2, 4):
        _lmp(bed, nprocs=n, stage="full", out=f"full.np{n}")
    ref = _atoms(bed / "full.np1")
    cref, fref = _contacts(bed / "full.np1.walls"), _contacts(bed / "full.np1.floor")
    # the walls act: paddle (mesh 1) and floor contacts, with non-zero tangential springs
    assert len(ref) == 1968 and (cref[:, 1] == 1).sum() > 10 and len(fref) > 500
    assert np.abs(cref[:, 14:17]).max() > 0 and np.abs(fref[:, 14:17]).max() > 0
    for n in (2, 4):
        got = _atoms(bed / f"full.np{n}")
        assert np.array_equal(got[:, 0], ref[:, 0])
        for cols in (slice(1, 4), slice(4, 7), slice(7, 10)):  # x, v, omega
            assert np.array_equal(got[:, cols], ref[:, cols]), f"{n} ranks: {_rel(got[:, cols], ref[:, cols]):.3g}"
        for name, cr in (("walls", cref), ("floor", fref)):
            c = _contacts(bed / f"full.np{n}.{name}")
            assert c.shape == cr.shape and np.array_equal(c, cr), f"{n} ranks, {name} contacts differ"


def test_restart_equals_split_run_bitwise(bed):
    _lmp(bed, stage="split", out="split.dump")
    _lmp(bed, stage="first", out="first.dump")
    _lmp(bed, stage="second", out="second.dump")
    log = open(bed / "log.second.1").read()
    assert "Resetting peratom fix info from restart file" in log
    a, b = _atoms(bed / "split.dump"), _atoms(bed / "second.dump")
    assert np.array_equal(a, b), "per-atom state differs after restart"
    ca, cb = _contacts(bed / "split.dump.walls"), _contacts(bed / "second.dump.walls")
    assert (ca[:, 1] == 1).sum() > 10  # paddle contacts, whose contact points give the mesh pose
    assert np.array_equal(ca, cb), "wall contacts, their history or the mesh pose differ after restart"
    fa, fb = _contacts(bed / "split.dump.floor"), _contacts(bed / "second.dump.floor")
    assert len(fa) > 500 and np.array_equal(fa, fb), "floor contacts or their history differ after restart"


def test_run_pre_no_equals_one_run_bitwise(bed):
    _lmp(bed, stage="full", steps=400, out="full400.dump")
    _lmp(bed, stage="continuous", steps=400, out="continuous400.dump")
    a, b = _atoms(bed / "full400.dump"), _atoms(bed / "continuous400.dump")
    assert len(a) == 1968 and np.array_equal(a, b), "run 200 + run 200 pre no differs from run 400"
    ca, cb = _contacts(bed / "full400.dump.walls"), _contacts(bed / "continuous400.dump.walls")
    assert (ca[:, 1] == 1).sum() > 10 and np.array_equal(ca, cb), "paddle contacts differ"
    fa, fb = _contacts(bed / "full400.dump.floor"), _contacts(bed / "continuous400.dump.floor")
    assert len(fa) > 500 and np.array_equal(fa, fb), "floor contacts differ"
