"""fix mesh/surface/stress against LIGGGHTS 3.8 (issue 10 acceptance A, mesh force/torque): the
oracle deck mesh_stress_resting, unchanged apart from the harness's atom_style/communicate
conversion, prints f_cad[1..9] every step (%.20g: every bit); each of the 3000 steps must equal the
recorded LIGGGHTS stress.txt (tolerance 0), serial and on 2 ranks (the force sum is an MPI sum).
Measured: bit-identical on both."""
import gzip
from pathlib import Path

import pytest

import oracle_harness as oh

ROOT = Path(__file__).resolve().parent.parent
CASE = ROOT / "data" / "liggghts-walls" / "mesh_stress_resting"
REF = ROOT / "data" / "liggghts-walls" / "mesh" / "mesh_stress_resting_stress.txt.gz"


def read_rows(lines):
    return {int(t[0]): [float(c) for c in t[1:]] for t in (l.split() for l in lines) if t and not t[0].startswith("#")}


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_mesh_force_and_torque_per_step_match_liggghts(plugin, tmp_path, nprocs):
    deck = oh.liggghts_to_lammps_deck((CASE / "in.liggghts").read_text(), plugin_path=plugin, syntax="3x")
    oh.run_lammps(deck, tmp_path, nprocs=nprocs, files=[CASE / "data.txt", CASE / "plate.stl"])
    got = read_rows((tmp_path / "stress.txt").read_text().splitlines())
    ref = read_rows(gzip.open(REF, "rt").read().splitlines())
    assert len(ref) == 3000 and set(ref) <= set(got)
    differ = [(step, col, got[step][col], r[col]) for step, r in sorted(ref.items()) for col in range(9)
              if got[step][col] != r[col]]
    assert not differ, f"{len(differ)} values differ, first (step, column, ours, LIGGGHTS): {differ[:3]}"
    # the force is really there: the plate carries the spheres (|F_z| near their weight)
    assert max(abs(r[2]) for r in ref.values()) > 1e-3
