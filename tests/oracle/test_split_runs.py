"""Split runs (`run N` + `run M`) with walls, against LIGGGHTS 3.8 run live and LAMMPS's built-in wall.

* A moving mesh keeps its node velocities across a run's setup, as LIGGGHTS 3.8 does: the linear
  pusher (fix move/mesh linear) is in contact with a sphere at the split (step 300), a zplane floor
  under both spheres; LIGGGHTS's own `run 300` + `run 200` and ours agree bitwise. (Zeroing the
  velocities at setup, as the plugin did before, departs from it by 5e-5 in v.)
* Every run's setup evaluates the forces once more, from the full-step velocities (the step itself
  used the half-step ones) and without advancing the history; the next step starts from those
  forces, so a split run departs from the continuous one. LAMMPS's built-in `fix wall/gran` does
  too (a sphere sliding on a damped zplane: 5e-7 relative in v after `run 200` + `run 200`). In
  LIGGGHTS 3.8 the departure is larger where a contact slides (4e-3 in v on the same sphere): its
  tangential damping acts only while the contact sticks, and the setup's slightly different normal
  force can turn a sliding contact into a sticking one for that evaluation. The plugin's split run
  is LIGGGHTS's own, bit for bit (the pusher with its floor, and the sliding sphere).
* `run M pre no` skips that setup: `run 300` + `run 200 pre no` equals `run 500` bitwise in LIGGGHTS,
  in the plugin and in the built-in (tests/python/test_walls_ranks_restart.py does it on a moving-
  mesh bed)."""
from pathlib import Path

import numpy as np
import pytest

import oracle_harness as oh

CASE = Path(__file__).resolve().parent.parent / "data" / "liggghts-walls" / "mesh_move_linear_pusher"
SPLIT, TOTAL = 300, 500


def _pusher_deck(runs):
    """The pusher case with the dump every 10 steps, spheres placed so that the plate touches
    sphere 1 from step ~0 (data_text), and `runs` instead of its run line."""
    out = []
    for line in (CASE / "in.liggghts").read_text().splitlines():
        if line.startswith("run "):
            out += runs
        else:
            out.append(line.replace("custom 1 dump.txt", "custom 10 dump.txt"))
    return "\n".join(out) + "\n"


def _data(tmp_path):
    """The case's data file with sphere 1 moved 0.1 mm towards the pusher (contact over steps
    ~0..850 instead of 1000..1850, so that the runs stay short)."""
    text = (CASE / "data.txt").read_text().replace("-0.005999999999999999 0.002", "-0.0061 0.002")
    assert text != (CASE / "data.txt").read_text()
    src = tmp_path / "case"
    src.mkdir()
    (src / "data.txt").write_text(text)
    (src / "pusher.stl").write_bytes((CASE / "pusher.stl").read_bytes())
    (src / "in.liggghts").write_text(_pusher_deck([f"run {TOTAL}"]))
    return src


def _liggghts(src, tmp_path, name, runs):
    return oh.read_dump(oh.run_liggghts(src, tmp_path / f"liggghts_{name}", deck_text=_pusher_deck(runs)))


def _ours(src, tmp_path, plugin, name, runs):
    deck = oh.liggghts_to_lammps_deck(_pusher_deck(runs), plugin_path=plugin, syntax="3x")
    return oh.read_dump(oh.run_lammps(deck, tmp_path / f"lammps_{name}", files=[src / "data.txt", src / "pusher.stl"]))


def _max_dv(a, b):
    assert sorted(a) == sorted(b)
    return max(float(np.abs(a[s]["v"] - b[s]["v"]).max()) for s in a)


@pytest.mark.liggghts
def test_split_run_with_moving_mesh_matches_liggghts(plugin, tmp_path):
    src = _data(tmp_path)
    split = [f"run {SPLIT}", f"run {TOTAL - SPLIT}"]
    l_cont = _liggghts(src, tmp_path, "cont", [f"run {TOTAL}"])
    l_split = _liggghts(src, tmp_path, "split", split)
    ours = _ours(src, tmp_path, plugin, "split", split)
    # the plate pushes sphere 1 at the split (x force), the floor carries both spheres (z force)
    f = l_cont[SPLIT]["f"]
    assert abs(f[0, 0]) > 1e-3 and np.all(np.abs(f[:, 2]) > 0)
    rep = oh.compare(l_split, ours, 0.0, label="split run, LIGGGHTS 3.8 vs plugin")
    assert rep.passed, rep.summary()
    # LIGGGHTS's own split departs from its continuous run (measured: 1.6e-5 m/s in v of 0.14 m/s)
    assert _max_dv(l_split, l_cont) > 0.0


@pytest.mark.liggghts
def test_run_pre_no_is_continuous(plugin, tmp_path):
    src = _data(tmp_path)
    pre_no = [f"run {SPLIT}", f"run {TOTAL - SPLIT} pre no"]
    l_cont = _liggghts(src, tmp_path, "cont", [f"run {TOTAL}"])
    for name, frames in (("LIGGGHTS", _liggghts(src, tmp_path, "pre_no", pre_no)),
                         ("plugin", _ours(src, tmp_path, plugin, "pre_no", pre_no))):
        rep = oh.compare(l_cont, frames, 0.0, label=f"{name}: run {SPLIT} + run {TOTAL - SPLIT} pre no vs run {TOTAL}")
        assert rep.passed, rep.summary()


# A sphere resting on a damped zplane wall, in LAMMPS's own syntax (the built-in fix wall/gran) and
# in LIGGGHTS's (the plugin's), run N + run M against run N+M.
BUILTIN_WALL = "fix floor all wall/gran hooke/history 2e5 NULL 3000 NULL 0.5 1 zplane 0 NULL"
PLUGIN_WALL = "fix floor all wall/gran model hooke tangential history primitive type 1 zplane 0"
RESTING = """units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
region box block -0.01 0.01 -0.01 0.01 0 0.02 units box
create_box 1 box
create_atoms 1 single 0 0 0.000999999 units box
set atom 1 diameter 0.002 density 2500
velocity all set 0.01 0 0
{pair}
neighbor 0.0005 bin
timestep 1e-6
{wall}
fix grav all gravity 9.81 vector 0 0 -1
fix integr all nve/sphere
dump d all custom 10 dump.txt id mass x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz
dump_modify d sort id format float %.17g
{runs}
"""
MATERIALS = """fix m1 all property/global youngsModulus peratomtype 5.e7
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
fix m5 all property/global characteristicVelocity scalar 1.0
pair_style gran model hooke tangential history
pair_coeff * *"""


def _liggghts_resting(tmp_path, name, runs):
    deck = RESTING.format(pair=MATERIALS, wall=PLUGIN_WALL, runs=runs).replace("atom_style sphere", "atom_style granular")
    deck = deck.replace("comm_modify vel yes", "communicate single vel yes")
    deck = deck.replace("format float %.17g", 'format "%d' + " %.17g" * 16 + '"')
    src = tmp_path / f"liggghts_src_{name}"
    src.mkdir()
    return oh.read_dump(oh.run_liggghts(src, tmp_path / f"liggghts_{name}", deck_text=deck))


@pytest.mark.parametrize("wall", ["builtin", "plugin"])
def test_primitive_wall_split_is_lammps_behaviour(plugin, tmp_path, wall):
    """The built-in wall and the plugin's both depart across a split (the setup's force evaluation)
    and both continue bitwise with `pre no`; the plugin's split run is LIGGGHTS 3.8's bit for bit."""
    if wall == "builtin":
        head, pair, line = "", "pair_style gran/hooke/history 2e5 NULL 3000 NULL 0.5 1\npair_coeff * *", BUILTIN_WALL
    else:
        head, pair, line = f"plugin load {plugin}\n", MATERIALS, PLUGIN_WALL
    runs = {"cont": "run 400", "split": "run 200\nrun 200", "pre_no": "run 200\nrun 200 pre no"}
    got = {k: oh.read_dump(oh.run_lammps(head + RESTING.format(pair=pair, wall=line, runs=r), tmp_path / k))
           for k, r in runs.items()}
    at = got["cont"][200]
    assert at["f"][0, 2] + 9.81 * at["mass"][0] > 0, "the sphere must touch the wall at the split"
    assert _max_dv(got["split"], got["cont"]) > 0.0
    if wall == "plugin":
        rep = oh.compare(_liggghts_resting(tmp_path, "split", runs["split"]), got["split"], 0.0, label="split, LIGGGHTS vs plugin")
        assert rep.passed, rep.summary()
    rep = oh.compare(got["cont"], got["pre_no"], 0.0, label=f"{wall}: run 200 + run 200 pre no vs run 400")
    assert rep.passed, rep.summary()
