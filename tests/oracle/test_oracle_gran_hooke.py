"""LIGGGHTS oracle for the no-history hooke law, every frame:
* 3.x syntax (`gran model hooke tangential no_history`) against LIGGGHTS 3.8 run live, serial and on 2
  MPI ranks: bit-identical (tolerance 0);
* 2.x syntax (`gran/hooke`) against the 2.x-semantics Python model (spec_check.py), serial: bit-identical;
* 2.x syntax against LIGGGHTS 3.8, serial: the 2.x damping expression rounds differently (measured: equal on
  hooke_oblique_nohistory, 1.1e-15 on multipair_hooke_nohist), asserted within 1e-14.
Without the built plugin (DEMBRIDGE_PLUGIN) they skip, which fails under ctest."""
import pytest

import oracle_harness as oh

CASES = ["hooke_oblique_nohistory", "multipair_hooke_nohist"]


@pytest.mark.plugin
@pytest.mark.liggghts
@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
@pytest.mark.parametrize("case", CASES)
def test_oracle_gran_hooke(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(case, rtol=0.0, nprocs=nprocs, live=True, syntax="3x", workdir=tmp_path, plugin=plugin)
    print("\n" + rep.summary())
    assert rep.passed, rep.summary()


@pytest.mark.plugin
@pytest.mark.parametrize("case", CASES)
def test_2x_syntax_matches_2x_model(plugin, tmp_path, case):
    rep = oh.check_case(case, rtol=0.0, semantics="2x", syntax="2x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()


@pytest.mark.plugin
@pytest.mark.liggghts
@pytest.mark.parametrize("case", CASES)
def test_2x_syntax_within_roundoff_of_liggghts(plugin, tmp_path, case):
    rep = oh.check_case(case, rtol=1e-14, live=True, syntax="2x", workdir=tmp_path, plugin=plugin)
    print("\n" + rep.summary())
    assert rep.passed, rep.summary()
