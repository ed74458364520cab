"""Insertion and mesh wear survive a restart, bit for bit, with tests/decks/in.insertion_restart:
insert/stream (vel gaussian, particles still in the extrusion volume at the restart), insert/pack
(volumefraction_region every 200 steps) and insert/rate/region (nparticles, all_in) from two
distributions of two templates, falling onto an STL plate that wears (wear finnie), 600 + 600 steps,
every fix inserting before and after step 600.
* `run 600` + write_restart + a new process that reads it, redefines the fixes and runs 600 steps
  equals `run 600` + `run 600` in one process (tolerance 0): the atoms (ids, type, x, v, omega,
  radius, mass), the per-triangle wear, and each fix's count and mass inserted; also when the
  one-rank restart file is continued on 2 ranks.
* `run 600` + `run 600 pre no` equals `run 1200`.
* An insert/rate/region that had inserted its whole total resumes after the restart when it is defined
  with a larger one (as LIGGGHTS 3.8).
* A restart with a changed seed or template stops with an ERROR naming the fix and what changed.
"""
import os
import shutil
import subprocess

import numpy as np
import pytest

import dembridge

HERE = os.path.dirname(os.path.abspath(__file__))
DECK = os.path.join(HERE, "..", "decks", "in.insertion_restart")
PLATE = os.path.join(HERE, "..", "data", "liggghts-walls", "mesh", "plate.stl")
FACE = os.path.join(HERE, "..", "data", "liggghts-insertion", "stream_face.stl")
END = 1200


def _lmp(wd, stage, out, nprocs=1, check=True, deck="in.insertion_restart", var=()):
    cmd = [dembridge.lmp_executable(), "-in", deck, "-screen", "none", "-nocite", "-log", f"log.{out}",
           "-var", "plugin", str(dembridge.plugin_path()), "-var", "stage", stage, "-var", "out", out]
    for k, v in var:
        cmd += ["-var", k, str(v)]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    return subprocess.run(cmd, cwd=wd, check=check, timeout=600, capture_output=True, text=True)


def _atoms(path):
    rows = [l.split() for l in open(path).read().split("ITEM: ATOMS")[1].splitlines()[1:] if l.strip()]
    return np.array(rows, dtype=float)  # sorted by id (write_dump modify sort id)


def _wear(path):
    tok = open(path).read().split()
    i = tok.index("wear")
    n = int(tok[tok.index("CELL_DATA") + 1])
    return np.array(tok[i + 5:i + 5 + n], dtype=float)


def _counts(path):
    return np.array(open(path).read().split(), dtype=float)


def _workdir(tmp_path_factory, name):
    wd = tmp_path_factory.mktemp(name)
    for f in (DECK, PLATE, FACE):
        shutil.copy(f, wd)
    return wd


@pytest.fixture(scope="module")
def split(tmp_path_factory):
    if not os.path.isfile(dembridge.plugin_path()):
        pytest.skip("plugin not built")
    wd = _workdir(tmp_path_factory, "insertion_split")
    _lmp(wd, "split", "split")
    return wd


def _assert_same(ref, got, label, out="second"):
    a, b = _atoms(ref / "split.atoms"), _atoms(got / f"{out}.atoms")
    # every fix went on inserting after the restart: 120 + 45 + 60 particles in all
    assert len(a) == 225, f"{len(a)} atoms"
    assert np.array_equal(a[:, 0], b[:, 0]), f"{label}: atom ids differ"
    for name, cols in (("type", [1]), ("x", [2, 3, 4]), ("v", [5, 6, 7]), ("omega", [8, 9, 10]),
                       ("radius", [11]), ("mass", [12])):
        bad = np.nonzero((a[:, cols] != b[:, cols]).any(axis=1))[0]
        assert bad.size == 0, f"{label}: {name} differs for atom {int(a[bad[0], 0])}"
    wa, wb = _wear(ref / f"split.wear_{END}.vtk"), _wear(got / f"{out}.wear_{END}.vtk")
    assert (wa > 0).all() and np.array_equal(wa, wb), f"{label}: wear {wa} vs {wb}"
    ca, cb = _counts(ref / "split.counts"), _counts(got / f"{out}.counts")
    assert ca[0::2].tolist() == [120, 45, 60] and np.array_equal(ca, cb), f"{label}: counts {ca} vs {cb}"


def _counts_at(log, step):
    """The inserted counts (stream, pack, rate) on the thermo line of `step` of the first run."""
    for line in open(log):
        w = line.split()
        if len(w) == 5 and w[0] == str(step):
            return [int(x) for x in w[2:]]
    raise AssertionError(f"no thermo line for step {step} in {log}")


@pytest.fixture(scope="module")
def restart_file(tmp_path_factory):
    """`run 600` + write_restart on one rank."""
    if not os.path.isfile(dembridge.plugin_path()):
        pytest.skip("plugin not built")
    wd = _workdir(tmp_path_factory, "insertion_restart")
    _lmp(wd, "first", "first")
    # at the restart every fix has inserted and has more to insert
    assert _counts_at(wd / "log.first", 600) == [79, 27, 44]
    return wd


def test_restart_equals_split_run_bitwise(split, restart_file):
    _lmp(restart_file, "second", "second")
    log = open(restart_file / "log.second").read()
    assert "Resetting global fix info from restart file" in log
    assert "Resetting peratom fix info from restart file" in log
    _assert_same(split, restart_file, "1 rank")


@pytest.mark.two_cores
def test_restart_read_on_two_ranks_equals_serial_split_run(split, restart_file):
    """The restart file of the one-rank run, continued on 2 ranks (insertion is rank-invariant)."""
    _lmp(restart_file, "second", "second_np2", nprocs=2)
    _assert_same(split, restart_file, "2 ranks", out="second_np2")


def test_run_pre_no_equals_one_run_bitwise(tmp_path_factory):
    wd = _workdir(tmp_path_factory, "insertion_continuous")
    _lmp(wd, "full", "full")
    _lmp(wd, "continuous", "cont")
    a, b = _atoms(wd / "full.atoms"), _atoms(wd / "cont.atoms")
    assert len(a) == 225 and np.array_equal(a, b), "run 600 + run 600 pre no differs from run 1200"
    assert np.array_equal(_wear(wd / f"full.wear_{END}.vtk"), _wear(wd / f"cont.wear_{END}.vtk"))
    assert np.array_equal(_counts(wd / "full.counts"), _counts(wd / "cont.counts"))


@pytest.mark.parametrize("old,new,expected", [
    ("insert/stream seed 49979687", "insert/stream seed 86028121",
     "Fix insert/stream (id ins_s): restart: seed 86028121 differs from the seed 49979687"),
    ("discrete 32452843 2", "discrete 86028121 2",
     "Fix particledistribution/discrete (id pdd1) restart: seed 86028121 differs from the seed 32452843"),
    ("label setup\n", "label setup\ntimestep 4e-5\n",
     "Fix insert/stream (id ins_s): the timestep (0.000040) differs from the one (0.000050) of the run that wrote"),
    ("radius constant 0.003", "radius constant 0.0025",
     "Fix particledistribution/discrete (id pdd1) restart: template pts2: its radius differs"),
])
def test_changed_definition_after_restart_is_an_error(restart_file, old, new, expected):
    text = open(restart_file / "in.insertion_restart").read()
    assert old in text
    (restart_file / "in.changed").write_text(text.replace(old, new))
    r = _lmp(restart_file, "second", "changed", check=False, deck="in.changed")
    log = open(restart_file / "log.changed").read()
    assert r.returncode != 0 and "ERROR" in log
    assert expected in log, log[-800:]


def test_wear_dropped_with_a_warning_when_wear_is_off_after_restart(restart_file):
    text = open(restart_file / "in.insertion_restart").read()
    (restart_file / "in.nowear").write_text(text.replace(" wear finnie", "").replace(
        "dump w all mesh/vtk 1 ${out}.wear_*.vtk wear cad", ""))
    _lmp(restart_file, "second", "nowear", deck="in.nowear")
    assert "WARNING: fix mesh/surface/stress (id cad) restart: the restart file holds the wear of this mesh, " \
           "but 'wear finnie' is off now" in open(restart_file / "log.nowear").read()


def test_finished_insertion_resumes_with_a_larger_total(tmp_path_factory):
    """insert/rate/region has inserted its 60 particles by step 800: restarted at 900 with
    nparticles 75 it inserts 15 more (with 60 it would stay done: the split-run tests above)."""
    wd = _workdir(tmp_path_factory, "insertion_resume")
    _lmp(wd, "first", "first", var=[("n1", 900)])
    assert _counts_at(wd / "log.first", 900)[2] == 60
    text = open(wd / "in.insertion_restart").read()
    (wd / "in.more").write_text(text.replace("pdd2 nparticles 60", "pdd2 nparticles 75"))
    _lmp(wd, "second", "more", deck="in.more", var=[("n1", 900), ("n2", 300)])
    assert "the total was raised after the restart, resuming at step 901" in open(wd / "log.more").read()
    assert _counts(wd / "more.counts")[4] == 75
