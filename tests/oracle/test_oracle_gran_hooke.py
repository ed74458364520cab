"""LIGGGHTS oracle for pair_style gran/hooke (issue 2, acceptance B): the plugin must agree with
LIGGGHTS 3.8 (run live) to <= 1e-12 relative at every frame, serial and on 2 MPI ranks.
Skipped when the plugin is not built (DEMBRIDGE_PLUGIN)."""
import pytest

import oracle_harness as oh


@pytest.mark.plugin
@pytest.mark.liggghts
@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("case", ["hooke_oblique_nohistory", "multipair_hooke_nohist"])
def test_oracle_gran_hooke(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(case, rtol=1e-12, nprocs=nprocs, live=True, workdir=tmp_path, plugin=plugin)
    print("\n" + rep.summary())
    assert rep.passed, rep.summary()
