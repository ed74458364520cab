"""Rolling friction, cohesion and Stokes viscous damping against independent references
(issue 4, acceptance A), serial and 2 ranks:
* 3.x syntax against the LIGGGHTS 3.8 binary (live), 3.8 semantics (cohesion outside the
  Coulomb limit unless tangential_reduce on);
* 2.x syntax against the 2.x-semantics Python model of the spec (cohesion always inside the limit).
Tolerances (norm-wise relative, oracle_harness.compare), measured on every frame:
* against LIGGGHTS serial: bit-identical (tolerance 0);
* on 2 ranks: 1e-11 (a pair split across ranks rounds differently, see RTOL_2_RANKS);
* against the 2.x model serial: 1e-14 (the Python model sums an atom's contacts in another order:
  measured 1.5e-15 on multipair_hertz_sjkr, 1.4e-16 on multipair_hertz_epsd, 0 on the two-particle cases)."""
import numpy as np
import pytest

import oracle_harness as oh

ROLLING = ["rolling_cdt", "rolling_epsd", "rolling_epsd2", "rolling_epsd3", "rolling_cdt_hooke_oblique"]
MULTIPAIR = ["multipair_hertz_cdt", "multipair_hertz_epsd", "multipair_hertz_epsd2", "multipair_hooke_epsd3",
             "multipair_hertz_sjkr", "multipair_hertz_sjkr2"]
COHESION_38 = ["cohesion_sjkr", "cohesion_sjkr2", "cohesion_sjkr_hooke_headon", "cohesion_sjkr_treduce",
               "rolling_epsd_cohesion_treduce"]
COHESION_2X = ["cohesion_sjkr_treduce", "rolling_epsd_cohesion_treduce"]  # 2.x = tangential_reduce on


# On 2 ranks a pair split across ranks is evaluated from both sides with i and j swapped (newton
# off), so n = ±del/r rounds differently; near a sign change of a small torque this shows at
# 1e-12 (measured 1.4e-12 in cohesion_sjkr's torque at step 1178, |torque| 5e-9 N m; 3.7e-14 in
# cohesion_sjkr_treduce, 6.6e-16 in multipair_hertz_sjkr).
RTOL_2_RANKS = 1e-11
RTOL_LIGGGHTS = {1: 0.0, 2: RTOL_2_RANKS}
RTOL_2X_MODEL = {1: 1e-14, 2: RTOL_2_RANKS}


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
@pytest.mark.parametrize("case", ROLLING + MULTIPAIR + COHESION_38)
def test_3x_syntax_matches_liggghts(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(case, rtol=RTOL_LIGGGHTS[nprocs], nprocs=nprocs, live=True, syntax="3x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
@pytest.mark.parametrize("case", ROLLING + MULTIPAIR + COHESION_2X)
def test_2x_syntax_matches_2x_model(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(case, rtol=RTOL_2X_MODEL[nprocs], nprocs=nprocs, semantics="2x", syntax="2x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()


def test_viscous_headon_matches_liggghts_while_approaching(plugin, tmp_path):
    """Until the normal velocity changes sign, 3.8's Stokes number and ours are the same. From then
    on 3.8 uses the signed St, which gives an effective restitution above MaximumRestitution; ours
    uses |St| (issue 4: restitution never above the maximum), so the frames after that differ."""
    # the approach phase is read from a live LIGGGHTS 3.8 run (no stored dump ships with the repository)
    ref = oh.read_dump(oh.run_liggghts("hooke_viscous_headon", tmp_path / "approach"))
    approaching = [s for s, fr in sorted(ref.items())
                   if (fr["v"][0] - fr["v"][1]) @ (fr["x"][0] - fr["x"][1]) < 0]
    last = max(s for s in approaching if all(t in approaching for t in range(0, s + 1)))
    assert last > 200, "the approach phase of the oracle must be long enough to compare"
    rep = oh.check_case("hooke_viscous_headon", rtol=0.0, syntax="3x", workdir=tmp_path, plugin=plugin,
                        steps=range(0, last + 1))
    assert rep.passed, rep.summary()


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_gas200_periodic_whole_run(plugin, tmp_path, nprocs):
    """200 polydisperse spheres, hertz + cdt, periodic, 6000 steps: with 3.8's rule that a separated
    pair keeps its springs until the next neighbour-rebuild step (issue 12), every frame is bit-identical
    (tolerance 0) on 1 and 2 ranks."""
    rep = oh.check_case("gas200_periodic", rtol=0.0, nprocs=nprocs, syntax="3x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()
    assert len(rep.steps_compared) == 31
