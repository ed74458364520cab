"""`-sf omp` / `suffix omp` with the plugin loaded (issue 12, acceptance C): LAMMPS looks for
STYLE/omp first, and its built-in gran/*/omp styles know neither the LIGGGHTS syntax nor our contact
history. The plugin registers those names, so the suffix must run the plugin's styles (threaded: they
log the threads used), and the results must not depend on the OpenMP thread count (`package omp N`).
Threaded results on a dense bed, LIGGGHTS syntaxes and ranks x threads: test_omp_threads.py."""
import os
import subprocess

import pytest

import dembridge

pytestmark = pytest.mark.two_cores  # OpenMP threads (2) in most tests

DECK = """
plugin load {plugin}
{suffix}
units lj
atom_style sphere
boundary p p f
newton off
comm_modify vel yes
region box block 0 8 0 8 0 16
create_box 1 box
region ins block 0.5 7.5 0.5 7.5 0.5 12
lattice sc 1.05
create_atoms 1 region ins
set type 1 diameter 1.0
set type 1 density 1.0
velocity all create 0.5 4928459 loop geom
{pair}
pair_coeff * *
compute c all pair/gran/local
compute fn all reduce sum c_c[4] inputs local
fix 1 all nve/sphere
fix 2 all gravity 1.0 vector 0 0 -1
fix 3 all wall/reflect zlo EDGE
timestep 0.001
thermo 100
thermo_style custom step ke c_fn
thermo_modify format float %20.15g
run 600
write_dump all custom final.dump id x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz modify sort id format float %.17g
"""

PAIRS = {
    "numeric_hooke_history": "pair_style gran/hooke/history 2000.0 NULL 50.0 NULL 0.5 1",
    "numeric_hertz_history": "pair_style gran/hertz/history 2000.0 NULL 50.0 NULL 0.5 1",
    "numeric_hooke": "pair_style gran/hooke 2000.0 NULL 50.0 NULL 0.5 1",
    "liggghts_2x_hertz": "\n".join([
        "fix m1 all property/global youngsModulus peratomtype 1.0e5",
        "fix m2 all property/global poissonsRatio peratomtype 0.3",
        "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5",
        "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5",
        "pair_style gran/hertz/history"]),
}


def _run(tmp_path, tag, pair, suffix_line, args):
    wd = tmp_path / tag
    wd.mkdir()
    (wd / "in.deck").write_text(DECK.format(plugin=dembridge.plugin_path(), suffix=suffix_line, pair=pair))
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive")
    p = subprocess.run([dembridge.lmp_executable(), "-in", "in.deck", "-log", "log.lammps", "-nocite", *args], cwd=wd,
                       env=env, capture_output=True, text=True, timeout=600)
    log = (wd / "log.lammps").read_text() if (wd / "log.lammps").exists() else ""
    assert p.returncode == 0 and "ERROR" not in log, p.stdout[-2000:] + p.stderr[-2000:]
    return log, (wd / "final.dump").read_text()


def _thermo(log):
    rows = [l.split() for l in log.splitlines() if l.strip() and l.split()[0].isdigit() and len(l.split()) == 3]
    assert len(rows) >= 7
    return rows


@pytest.mark.parametrize("name", sorted(PAIRS))
def test_sf_omp_runs_the_plugin_style_independent_of_threads(tmp_path, name):
    ref_log, ref_dump = _run(tmp_path, "plain", PAIRS[name], "", [])
    for threads in (1, 2):
        log, dump = _run(tmp_path, f"sf{threads}", PAIRS[name], "", ["-sf", "omp", "-pk", "omp", str(threads)])
        # compute pair/gran/local only accepts the plugin's pair styles, so the run itself shows it;
        # the summed normal force of the contacts must be non-zero (contacts really happen)
        assert _thermo(log) == _thermo(ref_log), f"-sf omp -pk omp {threads} changed the thermo output"
        assert dump == ref_dump, f"-sf omp -pk omp {threads}: final state differs from the plain plugin run"
        assert any(float(r[2]) > 0 for r in _thermo(log))
        assert f"/omp: {threads} OpenMP thread(s)" in log, "the plugin's threaded style did not report its threads"


def test_suffix_command_runs_the_plugin_style(tmp_path):
    pair = PAIRS["numeric_hooke_history"]
    ref_log, ref_dump = _run(tmp_path, "plain", pair, "", [])
    log, dump = _run(tmp_path, "suffix", pair, "package omp 2\nsuffix omp", [])
    assert dump == ref_dump and _thermo(log) == _thermo(ref_log)
    assert "gran/hooke/history/omp: 2 OpenMP thread(s)" in log

