"""Wall contact history follows its atom (brief: "all history survives migration, sorting, atom
insertion/deletion by other fixes, and restart") for `fix wall/gran` with LIGGGHTS syntax, primitive
and mesh walls at once.

Six "walkers" rest on a zplane primitive wall and a two-triangle mesh plate (both at z = 0), each with
tangential and epsd rolling springs: two slide across the plate's shared diagonal edge and across x = 0
(the rank boundary on 2 ranks), two stick (their springs hold them), one slides off the plate's edge
(the mesh contact ends, the plane contact stays), one is on the plane only. The walkers never touch each
other, so each walker's motion depends only on its own walls and its own history: it must be bitwise
the same whatever happens to other atoms.

Reference: the walkers alone on 1 rank, no sorting. Compared runs add 40 bystander spheres far from the
walls, created BEFORE the walkers, `fix pour` inserting 4 spheres after them at the first step and
`fix evaporate` deleting one bystander every 100 steps (each deletion moves the last local atom into the
freed slot: the poured spheres, then the walkers, from step 500 on 1 rank), atom sorting, 2 ranks, and
a restart into a new process. Positions, velocities, spins, forces, torques and the
per-contact wall output (history springs included) of the walkers are asserted bitwise equal.
"""
import os
import shutil

import numpy as np
import pytest

import dembridge
from lmp_runs import run_lmp
from dembridge import thermo_rows

pytestmark = pytest.mark.two_cores  # 2-rank cases against a reference run that every test shares

HERE = os.path.dirname(os.path.abspath(__file__))
PLATE = os.path.join(HERE, "..", "data", "liggghts-walls", "mesh_plate_diagonal", "plate.stl")

Z0 = 0.00099985  # rests on the walls (both at z = 0) with a small overlap
# x y vx vy omega_z: sliders across the diagonal and x = 0, stickers, one leaving the plate, one on the plane only
WALKERS = [(-0.004, 0.001, 1.5, 0.0, 0.0), (0.003, -0.003, -2.0, 0.0, 0.0), (-0.010, 0.006, 0.02, 0.0, 0.0),
           (0.012, -0.008, 0.0, 0.02, 0.0), (0.0195, 0.010, 0.5, 0.0, 0.0), (-0.030, -0.010, 0.0, 1.0, 50.0)]
NBYSTANDERS = 40
MODEL = "model hertz tangential history rolling_friction epsd"

MATERIALS = [
    "fix m1 all property/global youngsModulus peratomtype 5.e7",
    "fix m2 all property/global poissonsRatio peratomtype 0.3",
    "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
    "fix m5 all property/global characteristicVelocity scalar 1.0",
    "fix r1 all property/global coefficientRollingFriction peratomtypepair 1 0.1",
    "fix r2 all property/global coefficientRollingViscousDamping peratomtypepair 1 0.3",
]


def _settings(sort):
    return [f"atom_modify sort {sort} 0.0", "comm_modify vel yes", "neighbor 0.0005 bin",
            "neigh_modify delay 0", "timestep 1e-6"]


def _fixes(busy):
    lines = MATERIALS + [
        "fix cad all mesh/surface file plate.stl type 1",
        f"fix floor all wall/gran {MODEL} primitive type 1 zplane 0.0",
        f"fix plate all wall/gran {MODEL} mesh n_meshes 1 meshes cad",
        "fix integr all nve/sphere",
        "fix grav all gravity 9.81 vector 0.0 0.0 -1.0",
    ]
    if busy:  # bystanders deleted below the walls, new spheres poured in above them
        lines += ["region low block -0.035 0.035 -0.025 0.025 -0.028 -0.012 units box",
                  "region top block -0.03 0.03 -0.02 0.02 0.03 0.038 units box",
                  "fix evap all evaporate 100 1 low 5521",
                  "fix pour all pour 4 1 4767 region top diam one 0.002 dens 2500 2500 vol 0.05 50"]
    return lines


def _start(busy, sort, nprocs):
    lines = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f", "newton off"]
    if nprocs == 2:
        lines.append("processors 2 1 1")  # the boundary at x = 0
    lines += ["region box block -0.04 0.04 -0.03 0.03 -0.03 0.04 units box", "create_box 1 box"]
    if busy:
        lines += ["region bys block -0.035 0.035 -0.025 0.025 -0.028 -0.012 units box",
                  f"create_atoms 1 random {NBYSTANDERS} 8142 bys overlap 0.0025 maxtry 1000 units box"]
    first = NBYSTANDERS + 1 if busy else 1
    for x, y, *_ in WALKERS:
        lines.append(f"create_atoms 1 single {x} {y} {Z0} units box")
    lines += ["set group all diameter 0.002", "set group all density 2500",
              f"group walkers id {first}:{first + len(WALKERS) - 1}"]
    for k, (_, _, vx, vy, wz) in enumerate(WALKERS):
        lines.append(f"set atom {first + k} vx {vx} vy {vy} vz 0.0 omega 0.0 0.0 {wz}")
    lines += _settings(sort) + ["pair_style gran " + MODEL, "pair_coeff * *"] + _fixes(busy)
    return lines


def _finish():
    return ["compute cf all wall/gran/local floor", "compute cp all wall/gran/local plate",
            "dump df all local 1 floor.contacts c_cf[*]", "dump_modify df format float %.17g",
            "dump dp all local 1 plate.contacts c_cp[*]", "dump_modify dp format float %.17g",
            "dump dw walkers custom 1 walkers.dump id x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz",
            "dump_modify dw sort id format float %.17g", "run 0"]


def _run(tmp, busy, sort=0, nprocs=1, restart=False):
    tmp.mkdir()
    shutil.copy(PLATE, tmp / "plate.stl")
    thermo = ["thermo_style custom step atoms", "thermo 100"]
    lines = _start(busy, sort, nprocs) + thermo + ["run 2000"]
    if restart:
        run_lmp(tmp, lines + ["write_restart half.restart"], nprocs, name="in.first")
        lines = ["read_restart half.restart", "newton off"] + _settings(sort) + _fixes(busy) + thermo
    run_lmp(tmp, lines + ["run 2000"] + _finish(), nprocs)
    offset = NBYSTANDERS if busy else 0
    atoms = [r[1] for r in thermo_rows(tmp / "in.deck.log")]
    return atoms, _walkers(tmp / "walkers.dump", offset), {w: _contacts(tmp / f"{w}.contacts", offset)
                                                         for w in ("floor", "plate")}


def _walkers(path, offset):
    rows = [l.split() for l in path.read_text().split("ITEM: ATOMS")[-1].splitlines()[1:] if l.strip()]
    a = np.array(rows, dtype=float)
    a[:, 0] -= offset
    return a


def _contacts(path, offset):
    rows = [l.split() for l in path.read_text().split("ITEM: ENTRIES")[-1].splitlines()[1:] if l.strip()]
    a = np.array(rows, dtype=float).reshape(len(rows), -1)
    a[:, 0] -= offset
    return a[np.lexsort((a[:, 2], a[:, 1], a[:, 0]))]


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    if not os.path.isfile(dembridge.plugin_path()):
        pytest.skip("plugin not built")
    return _run(tmp_path_factory.mktemp("walls") / "reference", busy=False)


def test_reference_exercises_the_history(reference):
    atoms, walkers, contacts = reference
    assert set(atoms) == {len(WALKERS)}
    assert walkers.shape == (len(WALKERS), 16)
    plane, plate = contacts["floor"], contacts["plate"]
    # every walker still on the plane; the one that left the plate has no plate contact
    assert sorted(plane[:, 0]) == [1, 2, 3, 4, 5, 6]
    assert 5 not in plate[:, 0] and {1, 2, 3, 4} <= set(plate[:, 0])
    assert plate[:, 2].min() >= 1 and plate[:, 2].max() <= 2  # triangle ids of the two-triangle plate
    # every walker's tangential spring on the plane is loaded (5e-9..5e-8 m), and rolling springs too:
    # a lost or swapped history would change the motion
    assert np.abs(plane[:, 14:17]).max(axis=1).min() > 1e-9
    assert np.abs(np.vstack([plane[:, 17:20], plate[:, 17:20]])).max() > 1e-9
    # the sliders crossed the diagonal edge and x = 0
    x = dict(zip(walkers[:, 0].astype(int), walkers[:, 1]))
    assert x[1] > 0.001 and x[2] < -0.003 and x[5] > 0.02


@pytest.mark.parametrize("case", ["delete_insert", "delete_insert_sort_2ranks", "delete_insert_sort_2ranks_restart"])
def test_walkers_bitwise_equal_to_reference(reference, tmp_path, case):
    kw = {"delete_insert": dict(), "delete_insert_sort_2ranks": dict(sort=10, nprocs=2),
          "delete_insert_sort_2ranks_restart": dict(sort=10, nprocs=2, restart=True)}[case]
    atoms, walkers, contacts = _run(tmp_path / case, busy=True, **kw)
    _, ref_walkers, ref_contacts = reference
    # the other fixes did their work: spheres poured in, bystanders deleted (one per 100 steps)
    assert max(atoms) > atoms[0] and atoms[-1] < max(atoms) - 15
    np.testing.assert_array_equal(walkers, ref_walkers)
    for wall in ("floor", "plate"):
        np.testing.assert_array_equal(contacts[wall], ref_contacts[wall])


def test_restart_with_another_wall_model_is_refused(tmp_path):
    """The restart file holds 7 values per wall contact (tangential + epsd rolling history); a wall fix
    defined after read_restart with tangential history only (4 values per contact) must not read them as
    garbage: ERROR naming the fix."""
    if not os.path.isfile(dembridge.plugin_path()):
        pytest.skip("plugin not built")
    from test_bad_input import run_deck  # one fresh in-process LAMMPS, returns the ERROR text

    shutil.copy(PLATE, tmp_path / "plate.stl")
    run_lmp(tmp_path, _start(False, 0, 1) + ["run 200", "write_restart half.restart"], 1, name="in.first")
    fixes = [l.replace(MODEL, "model hertz tangential history").replace("file plate.stl", f"file {tmp_path / 'plate.stl'}")
             for l in _fixes(False)]
    err = run_deck([f"read_restart {tmp_path / 'half.restart'}", "newton off"] + _settings(0) + fixes + ["run 1"])
    assert err is not None
    assert "fix floor wall/gran" in err and "not whole records of 4 values" in err and "define the fix as before" in err
