"""fix wall/gran (LIGGGHTS 3.x syntax) against LIGGGHTS 3.8 run live (issue 10, acceptance A):
every small wall case of tests/data/liggghts-walls/ (copied from the walls oracle), deck unchanged
apart from the atom_style/communicate lines the harness converts, serial and on 2 ranks. Every
frame must agree to 1e-12 (norm-wise relative, see oracle_harness.compare); in practice they are
bit-identical."""
from pathlib import Path

import pytest

import oracle_harness as oh

DATA = Path(__file__).resolve().parent.parent / "data" / "liggghts-walls"

PRIMITIVE_CASES = [
    "zplane_hooke_headon", "zplane_hertz_headon", "zplane_hertz_from_below", "zplane_hertz_oblique_epsd_sjkr",
    "zplane_hooke_oblique_cdt_sjkr2_walltype2", "zplane_bounce_history_reset", "zcylinder_hertz_inside_outside",
]


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("case", PRIMITIVE_CASES)
def test_primitive_wall_matches_liggghts(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(DATA / case, rtol=1e-12, nprocs=nprocs, live=True, syntax="3x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()
