"""The plugin's pair styles threaded under LAMMPS's OPENMP conventions (issue 12 "Threads", acceptance C).

With `package omp 2` and `-sf omp` (or `suffix omp`) the plugin's STYLE/omp runs its pair compute on
2 OpenMP threads: the style logs the threads that took part ("dembridge pair_style X/omp: 2 OpenMP
thread(s)"), which also shows that the built-in gran/*/omp did not run (they print no such line and
LAMMPS's `compute pair/gran/local` of the plugin rejects them). The threads split the neighbour
list by atom and every atom sums its contacts in the serial loop's order, so the reference is the
plain plugin style on 1 thread and the tolerance is zero: thermo (ke, pressure, summed normal
force) and every per-atom value (x, v, omega, f, torque at 17 digits) must be bit-identical after
the run, on 1 and 2 MPI ranks, and two 2-thread runs must agree bit for bit.

The deck is a dense polydisperse bed: 1000 spheres (diameters 0.96-1.0) on a lattice of spacing
1.0 falling 0.5 onto a floor under gravity 10 and settling for 2000 steps (kinetic energy 4.0 at
step 500, 0.007 at step 2000, positive pressure): about 6 neighbours per atom, most in persistent
contact with shear history. OMP_WAIT_POLICY=passive keeps the 2-thread runs from spinning against a loaded machine.
"""
import os
import re
import subprocess

import pytest

import dembridge

pytestmark = pytest.mark.two_cores  # OpenMP threads (2) in most tests

DENSE = """
plugin load {plugin}
{suffix}
units lj
atom_style sphere
boundary p p f
newton {newton}
comm_modify vel yes
region box block 0 10 0 10 0 14
create_box 1 box
lattice sc 1.0
region bed block 0 10 0 10 0.5 10.5
create_atoms 1 region bed
variable d atom 0.96+0.04*random(0,1,8273)
set group all diameter v_d
set type 1 density 1.0
velocity all create 0.2 4928459 loop geom
{pair}
pair_coeff * *
compute c all pair/gran/local
compute fn all reduce sum c_c[4] inputs local
fix 1 all nve/sphere
fix 2 all gravity 10.0 vector 0 0 -1
fix 3 all wall/reflect zlo EDGE
neigh_modify delay 0
timestep 0.001
thermo 250
thermo_style custom step ke press c_fn
thermo_modify format float %20.15g
run 2000
write_dump all custom final.dump id x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz modify sort id format float %.17g
"""

MATERIALS_2X = "\n".join([
    "fix m1 all property/global youngsModulus peratomtype 1.0e5",
    "fix m2 all property/global poissonsRatio peratomtype 0.3",
    "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5",
    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5"])

PAIRS = {
    "numeric_hooke_history": "pair_style gran/hooke/history 2000.0 NULL 50.0 NULL 0.5 1",
    "numeric_hertz_history": "pair_style gran/hertz/history 2000.0 NULL 50.0 NULL 0.5 1",
    "liggghts_2x_hertz": MATERIALS_2X + "\npair_style gran/hertz/history",
    "liggghts_2x_hooke_stiffness": "\n".join([
        "fix k1 all property/global kn peratomtypepair 1 2000.0",
        "fix k2 all property/global kt peratomtypepair 1 1000.0",
        "fix k3 all property/global gamman peratomtypepair 1 50.0",
        "fix k4 all property/global gammat peratomtypepair 1 25.0",
        "fix k5 all property/global coefficientFriction peratomtypepair 1 0.5",
        "pair_style gran/hooke/history/stiffness"]),
    "liggghts_3x_hertz_rolling_cohesion": "\n".join([
        MATERIALS_2X,
        "fix m5 all property/global coefficientRollingFriction peratomtypepair 1 0.1",
        "fix m6 all property/global coefficientRollingViscousDamping peratomtypepair 1 0.1",
        "fix m7 all property/global cohesionEnergyDensity peratomtypepair 1 50.0",
        "pair_style gran model hertz tangential history cohesion sjkr rolling_friction epsd"]),
}

THREADS_LINE = re.compile(r"dembridge pair_style (\S+)/omp: (\d+) OpenMP thread\(s\)")


def _run(tmp_path, tag, pair, suffix_line="", args=(), nprocs=1, newton="off", threads_env="1"):
    wd = tmp_path / tag
    wd.mkdir()
    (wd / "in.deck").write_text(DENSE.format(plugin=dembridge.plugin_path(), suffix=suffix_line, pair=pair, newton=newton))
    env = dict(os.environ, OMP_NUM_THREADS=threads_env, OMP_WAIT_POLICY="passive")
    cmd = [dembridge.lmp_executable(), "-in", "in.deck", "-log", "log.lammps", "-nocite", *args]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    p = subprocess.run(cmd, cwd=wd, env=env, capture_output=True, text=True, timeout=900)
    log = (wd / "log.lammps").read_text() if (wd / "log.lammps").exists() else ""
    assert p.returncode == 0 and "ERROR" not in log, p.stdout[-3000:] + p.stderr[-3000:]
    return log, (wd / "final.dump").read_text()


def _thermo(log):
    rows = [l.split() for l in log.splitlines() if l.strip() and l.split()[0].isdigit() and len(l.split()) == 4]
    assert len(rows) == 9, log[-2000:]
    return rows


def _threads_used(log):
    found = THREADS_LINE.findall(log)
    assert found, "no dembridge /omp pair style ran (the log has no thread report)"
    return {int(n) for _, n in found}


def _dense_enough(log):
    # the bed must really be settled and loaded: positive pressure and contact forces at every frame
    # after the start, and little kinetic energy left at the end
    rows = _thermo(log)
    assert all(float(r[3]) > 0 and float(r[2]) > 0 for r in rows[1:]), rows
    assert float(rows[-1][1]) < 0.05 * max(float(r[1]) for r in rows), rows


@pytest.mark.parametrize("name", sorted(PAIRS))
def test_two_threads_bit_identical_to_one_thread(tmp_path, name):
    ref_log, ref_dump = _run(tmp_path, "plain", PAIRS[name])
    assert not THREADS_LINE.search(ref_log)
    _dense_enough(ref_log)
    log, dump = _run(tmp_path, "sf2", PAIRS[name], args=["-sf", "omp", "-pk", "omp", "2"])
    assert _threads_used(log) == {2}
    assert _thermo(log) == _thermo(ref_log), "2 threads changed the thermo output"
    assert dump == ref_dump, "2 threads: final per-atom state differs from the 1-thread plain style"


def test_two_thread_runs_are_deterministic_and_suffix_command_threads(tmp_path):
    pair = PAIRS["liggghts_2x_hertz"]
    log_a, dump_a = _run(tmp_path, "a", pair, suffix_line="package omp 2\nsuffix omp")
    log_b, dump_b = _run(tmp_path, "b", pair, suffix_line="package omp 2\nsuffix omp")
    assert _threads_used(log_a) == {2} and _threads_used(log_b) == {2}
    assert dump_a == dump_b and _thermo(log_a) == _thermo(log_b)
    _dense_enough(log_a)


def test_package_omp_thread_count_is_followed(tmp_path):
    # -sf omp alone takes OMP_NUM_THREADS (LAMMPS's 'package omp 0'); 'package omp 1' forces one
    log3, dump3 = _run(tmp_path, "env3", PAIRS["numeric_hooke_history"], args=["-sf", "omp"], threads_env="3")
    log1, dump1 = _run(tmp_path, "pk1", PAIRS["numeric_hooke_history"], args=["-sf", "omp", "-pk", "omp", "1"], threads_env="3")
    assert _threads_used(log3) == {3} and _threads_used(log1) == {1}
    assert dump3 == dump1


def test_explicit_omp_style_name_is_the_plugin(tmp_path):
    # 'pair_style gran/hooke/history/omp' typed in a deck: the plugin's, not LAMMPS's built-in
    pair = "pair_style gran/hooke/history/omp 2000.0 NULL 50.0 NULL 0.5 1"
    ref_log, ref_dump = _run(tmp_path, "plain", PAIRS["numeric_hooke_history"])
    log, dump = _run(tmp_path, "explicit", pair, suffix_line="package omp 2")
    assert _threads_used(log) == {2} and dump == ref_dump


def test_newton_on_without_history(tmp_path):
    # gran/hooke has no history and accepts newton on: ghost atoms receive their share too
    pair = "pair_style gran/hooke 2000.0 NULL 50.0 NULL 0.5 1"
    ref_log, ref_dump = _run(tmp_path, "plain", pair, newton="on")
    log, dump = _run(tmp_path, "sf2", pair, args=["-sf", "omp", "-pk", "omp", "2"], newton="on")
    assert _threads_used(log) == {2} and dump == ref_dump and _thermo(log) == _thermo(ref_log)


def test_two_ranks_two_threads(tmp_path):
    pair = PAIRS["numeric_hertz_history"]
    ref_log, ref_dump = _run(tmp_path, "np2", pair, nprocs=2)
    log, dump = _run(tmp_path, "np2sf2", pair, args=["-sf", "omp", "-pk", "omp", "2"], nprocs=2)
    assert _threads_used(log) == {2}
    assert dump == ref_dump and _thermo(log) == _thermo(ref_log)


def test_contact_error_inside_a_thread_stops_cleanly(tmp_path):
    # an ERROR raised by a worker thread (coincident spheres, tests/decks/in.coincident) must reach
    # LAMMPS as the same clear message as on 1 thread, not terminate() the process from the thread
    deck = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "decks", "in.coincident")
    (tmp_path / "in.w").write_text(f"package omp 2\nplugin load {dembridge.plugin_path()}\nsuffix omp\ninclude {deck}\n")
    res = subprocess.run([dembridge.lmp_executable(), "-in", "in.w", "-var", "dx", "0.0", "-log", "log"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120, env=dict(os.environ, OMP_WAIT_POLICY="passive"))
    out = res.stdout + res.stderr
    assert res.returncode != 0
    assert re.search(r"ERROR.*pair_style gran/hooke/history: atom 1 at .* and atom 2 at .* are coincident", out), out[-2000:]
    assert "terminate called" not in out and "Segmentation" not in out


def _hybrid_deck_pair():
    # two atom types, a pair_style hybrid of two plugin styles (hooke for 1-1 and 1-2, hertz for 2-2);
    # compute pair/gran/local does not take hybrid, so the 4th thermo column is the rotational energy
    pair = "\n".join([
        "set type 1 type/fraction 2 0.5 77123",
        "pair_style hybrid gran/hooke/history 2000.0 NULL 50.0 NULL 0.5 1 gran/hertz/history 3000.0 NULL 60.0 NULL 0.4 1",
        "pair_coeff 1 1 gran/hooke/history",
        "pair_coeff 1 2 gran/hooke/history",
        "pair_coeff 2 2 gran/hertz/history",
        "compute rot all erotate/sphere"])
    return pair


def _run_hybrid(tmp_path, tag, args=(), suffix_line=""):
    deck = DENSE.replace("create_box 1 box", "create_box 2 box").replace("set type 1 density 1.0", "set group all density 1.0")
    deck = deck.replace("compute c all pair/gran/local\ncompute fn all reduce sum c_c[4] inputs local\n", "")
    deck = deck.replace("pair_coeff * *\n", "").replace("c_fn", "c_rot")
    wd = tmp_path / tag
    wd.mkdir()
    (wd / "in.deck").write_text(deck.format(plugin=dembridge.plugin_path(), suffix=suffix_line, pair=_hybrid_deck_pair(),
                                            newton="off"))
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive")
    p = subprocess.run([dembridge.lmp_executable(), "-in", "in.deck", "-log", "log.lammps", "-nocite", *args], cwd=wd, env=env,
                       capture_output=True, text=True, timeout=900)
    log = (wd / "log.lammps").read_text() if (wd / "log.lammps").exists() else ""
    assert p.returncode == 0 and "ERROR" not in log, p.stdout[-3000:] + p.stderr[-3000:]
    return log, (wd / "final.dump").read_text()


@pytest.mark.parametrize("how", ["sf", "suffix"])
def test_pair_hybrid_of_omp_sub_styles(tmp_path, how):
    # -sf omp / suffix omp turn each sub-style of pair hybrid into the plugin's /omp twin: both run
    # on 2 threads (each logs its report) and the run is bit-identical to plain hybrid on 1 thread
    ref_log, ref_dump = _run_hybrid(tmp_path, "plain")
    assert not THREADS_LINE.search(ref_log)
    _dense_enough(ref_log)
    if how == "sf":
        log, dump = _run_hybrid(tmp_path, "sf2", args=["-sf", "omp", "-pk", "omp", "2"])
    else:
        log, dump = _run_hybrid(tmp_path, "suffix2", suffix_line="package omp 2\nsuffix omp")
    assert sorted(THREADS_LINE.findall(log)) == [("gran/hertz/history", "2"), ("gran/hooke/history", "2")], log[-3000:]
    assert _thermo(log) == _thermo(ref_log), "2 threads changed the thermo output of pair hybrid"
    assert dump == ref_dump, "2 threads: final per-atom state of pair hybrid differs from 1 thread"
