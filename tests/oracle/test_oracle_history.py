"""History pair styles against independent references (issue 3, acceptance A), serial and 2 ranks:
* 3.x syntax (`pair_style gran model ...`) against the LIGGGHTS 3.8 binary, run live;
* 2.x syntax (`gran/hooke/history` ...) against the 2.x-semantics Python model of the spec
  (`spec_check.py`, GRAN_SEMANTICS=2x), since no 2.x binary exists.
Every frame of every case must agree to 1e-12 (norm-wise relative, see oracle_harness.compare)."""
import pytest

import oracle_harness as oh

CASES = [
    "hooke_headon", "hertz_headon", "hooke_oblique", "hertz_oblique",
    "hooke_oblique_tdamp_off", "hertz_oblique_tdamp_off",
    "hooke_stiffness_oblique", "hertz_stiffness_oblique", "hooke_stiffness_absdamp_oblique",
    "two_types_hooke", "bounce_smallskin",
    "multipair_hooke", "multipair_hertz", "multipair_hertz_tdoff",
    "multipair_hooke_stiffness", "multipair_hooke_stiffness_abs", "multipair_hertz_stiffness",
]


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("case", CASES)
def test_3x_syntax_matches_liggghts(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(case, rtol=1e-12, nprocs=nprocs, live=True, syntax="3x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("case", CASES)
def test_2x_syntax_matches_2x_model(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(case, rtol=1e-12, nprocs=nprocs, semantics="2x", syntax="2x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()
