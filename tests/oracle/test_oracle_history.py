"""History pair styles against independent references (issue 3, acceptance A), serial and 2 ranks:
* 3.x syntax (`pair_style gran model ...`) against the LIGGGHTS 3.8 binary, run live;
* 2.x syntax (`gran/hooke/history` ...) against the 2.x-semantics Python model of the spec
  (`spec_check.py`, GRAN_SEMANTICS=2x), since no 2.x binary exists.
Every frame of every case is bit-identical (tolerance 0, see oracle_harness.compare) on 1 and 2 ranks."""
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


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
@pytest.mark.parametrize("case", CASES)
def test_3x_syntax_matches_liggghts(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(case, rtol=0.0, nprocs=nprocs, live=True, syntax="3x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
@pytest.mark.parametrize("case", CASES)
def test_2x_syntax_matches_2x_model(plugin, tmp_path, case, nprocs):
    rep = oh.check_case(case, rtol=0.0, nprocs=nprocs, semantics="2x", syntax="2x", workdir=tmp_path, plugin=plugin)
    assert rep.passed, rep.summary()


def test_kt_to_kn_user_matches_liggghts(plugin, tmp_path):
    """`ktToKnUser on` (hooke: kt = 0.285714286 kn, LIGGGHTS's rounded 2/7, instead of kt = kn) on
    hooke_oblique, whose contact sticks and slides: every frame equal to live LIGGGHTS 3.8 (tolerance 0).
    The tangential spring really changes: the same deck without the keyword differs at 1e-3. Serial: the
    2-rank path of this contact is hooke_oblique's above."""
    case = tmp_path / "hooke_oblique_kt_to_kn_user"
    src = oh.case_dir("hooke_oblique")
    case.mkdir()
    (case / "data.txt").write_text((src / "data.txt").read_text())
    deck = (src / "in.liggghts").read_text()
    plain = "pair_style      gran model hooke tangential history\n"
    assert plain in deck
    (case / "in.liggghts").write_text(deck.replace(plain, plain.rstrip("\n") + " ktToKnUser on\n"))
    rep = oh.check_case(case, rtol=0.0, live=True, syntax="3x", workdir=tmp_path / "run", plugin=plugin)
    assert rep.passed, rep.summary()
    without = oh.read_dump(oh.run_liggghts(src, tmp_path / "without"))
    with_kt = oh.read_dump(tmp_path / "run" / "liggghts" / "dump.txt")
    assert not oh.compare(without, with_kt, 1e-3, quantities=("f",)).passed
