"""Bad input gets a LAMMPS ERROR naming the command, the argument and what was expected
(spec granular-models §2, §3, §10). One fresh LAMMPS instance per case; the plugin stays loaded."""
import pytest

from dembridge import new_lammps

MATERIAL = [
    "fix m1 all property/global youngsModulus peratomtype 5.e7",
    "fix m2 all property/global poissonsRatio peratomtype 0.3",
    "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
    "fix m5 all property/global characteristicVelocity scalar 1.0",
]


def base(units="si", atom_style="sphere", comm_vel=True, ntypes=1, atom_type=1):
    lines = [f"units {units}", f"atom_style {atom_style}", "boundary f f f", "newton off"]
    if comm_vel:
        lines.append("comm_modify vel yes")
    lines += [
        "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05",
        f"create_box {ntypes} box",
        f"create_atoms {atom_type} single -0.0049 0 0 units box",
        f"create_atoms {atom_type} single 0.0049 0 0 units box",
    ]
    if atom_style == "sphere":
        lines.append("set group all diameter 0.01 density 2500")
    return lines


def run_deck(lines):
    """Runs the lines; returns the ERROR message or None."""
    lmp = new_lammps()
    try:
        for line in lines:
            lmp.command(line)
        return None
    except Exception as e:  # the lammps module raises Exception with the ERROR text
        return str(e)
    finally:
        lmp.close()


def replace(lines, prefix, new):
    return [new if l.startswith(prefix) else l for l in lines]


GOOD = base() + MATERIAL + ["pair_style gran/hooke", "pair_coeff * *", "timestep 1e-6", "fix i all nve/sphere", "run 1"]

CASES = {
    # fix property/global parsing (spec §3)
    "prop_not_enough_args": (GOOD[:8] + ["fix m1 all property/global youngsModulus peratomtype"],
                             ["Fix property/global (id m1)", "not enough arguments"]),
    "prop_unknown_style": (GOOD[:8] + ["fix m1 all property/global youngsModulus peratom 5e7"],
                           ["(id m1)", "unknown style 'peratom'", "peratomtype"]),
    "prop_not_a_number": (GOOD[:8] + ["fix m1 all property/global youngsModulus peratomtype 5e7x"],
                          ["youngsModulus", "'5e7x' is not a finite number"]),
    "prop_nonsquare_pair": (GOOD[:8] + ["fix m4 all property/global coefficientFriction peratomtypepair 2 0.3 0.3"],
                            ["(id m4)", "N*N total values", "2 columns and 2 values"]),
    "prop_asymmetric_pair": (GOOD[:8] + ["fix m4 all property/global coefficientFriction peratomtypepair 2 0.3 0.2 0.25 0.3"],
                             ["(id m4)", "must be symmetric", "types (1,2) differs from (2,1)"]),
    "prop_matrix_not_multiple": (GOOD[:8] + ["fix m4 all property/global coefficientFriction matrix 2 0.3 0.2 0.25"],
                                 ["coefficientFriction", "multiple of the number of columns"]),
    "prop_scalar_two_values": (GOOD[:8] + ["fix m5 all property/global characteristicVelocity scalar 1.0 2.0"],
                               ["characteristicVelocity", "exactly 1 value"]),
    "prop_duplicate_name": (GOOD[:8] + MATERIAL + ["fix m6 all property/global poissonsRatio peratomtype 0.25"],
                            ["(id m6)", "already a fix that registers a variable of the same name 'poissonsRatio'", "fix m2"]),
    "prop_bad_ncols": (GOOD[:8] + ["fix m4 all property/global coefficientFriction peratomtypepair two 0.3"],
                       ["number of columns as a positive integer", "'two'"]),
    # pair requirements (spec §2)
    "req_atom_style": (replace(base(atom_style="atomic"), "set group", "mass 1 1.0") + MATERIAL
                       + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                       ["pair_style gran/hooke", "requires atom style sphere"]),
    "req_comm_vel": (base(comm_vel=False) + MATERIAL + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                     ["pair_style gran/hooke", "comm_modify vel yes"]),
    "req_units": (base(units="metal") + MATERIAL + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                  ["pair_style gran/hooke", "unit system 'metal'", "si"]),
    "req_types_from_1": (base(ntypes=2, atom_type=2) + [l.replace("peratomtype 5.e7", "peratomtype 5.e7 5.e7")
                                                        .replace("peratomtype 0.3", "peratomtype 0.3 0.3")
                                                        .replace("peratomtypepair 1 0.7", "peratomtypepair 2 0.7 0.7 0.7 0.7")
                                                        .replace("peratomtypepair 1 0.3", "peratomtypepair 2 0.3 0.3 0.3 0.3")
                                                        for l in MATERIAL] + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                         ["atom types must start from 1", "smallest type present is 2"]),
    "req_pair_coeff_args": (base() + MATERIAL + ["pair_style gran/hooke", "pair_coeff * * 1.0 2.0"],
                            ["pair_coeff for gran/hooke", "pair_coeff * *", "got 4 arguments"]),
    # material properties (spec §3 look-up, §10 ranges)
    "mat_missing_charvel": (base() + MATERIAL[:4] + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                            ["characteristicVelocity", "as requested by pair_style gran/hooke"]),
    "mat_wrong_kind": (base() + [MATERIAL[0].replace("peratomtype 5.e7", "peratomtypepair 1 5.e7")] + MATERIAL[1:]
                       + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                       ["peratomtype style required for fix property/global variable youngsModulus", "gran/hooke"]),
    "mat_length": (base(ntypes=2) + ["create_atoms 2 single 0.02 0 0 units box", "set group all diameter 0.01 density 2500"]
                   + MATERIAL + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                   ["Length not sufficient for variable youngsModulus", "atom types up to 2"]),
    "mat_restitution_range": (base() + replace(MATERIAL, "fix m3", "fix m3 all property/global coefficientRestitution peratomtypepair 1 1.2")
                              + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                              ["0.05 < coefficientRestitution <= 1 required", "1.2"]),
    "mat_poisson_range": (base() + replace(MATERIAL, "fix m2", "fix m2 all property/global poissonsRatio peratomtype 0.6")
                          + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                          ["0 <= poissonsRatio <= 0.5 required", "0.6"]),
    "mat_young_low_si": (base() + replace(MATERIAL, "fix m1", "fix m1 all property/global youngsModulus peratomtype 1e5")
                         + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                         ["youngsModulus >= 5e6 required for SI units", "sanity_checks off"]),
    "mat_charvel_low": (base() + replace(MATERIAL, "fix m5", "fix m5 all property/global characteristicVelocity scalar 0.001")
                        + ["pair_style gran/hooke", "pair_coeff * *", "run 0"],
                        ["characteristicVelocity >= 1e-2 required for SI units"]),
    # pair_style keywords (spec §1.1, fixed quirks of §12.3)
    "kw_unknown": (base() + MATERIAL + ["pair_style gran/hooke rolling_frixion cdt"],
                   ["pair_style gran/hooke", "unknown keyword 'rolling_frixion'"]),
    "kw_bad_on_off": (base() + MATERIAL + ["pair_style gran/hooke tangential_damping maybe"],
                      ["expecting 'on' or 'off' after keyword 'tangential_damping'", "'maybe'"]),
    "kw_epsd_without_history": (base() + MATERIAL + ["pair_style gran/hooke rolling_friction epsd2"],
                                ["rolling_friction epsd", "needs per-contact history"]),
    "kw_absolute_damping_hooke": (base() + MATERIAL + ["pair_style gran/hooke absolute_damping on"],
                                  ["'absolute_damping' is only available with the hooke stiffness styles"]),
    # history styles (issue 3, acceptance E)
    "hist_newton_on": ([l.replace("newton off", "newton on") for l in base()] + MATERIAL
                       + ["pair_style gran/hertz/history", "pair_coeff * *", "run 0"],
                       ["pair_style gran/hertz/history", "requires 'newton off'"]),
    "hist_missing_friction": (base() + MATERIAL[:3] + ["pair_style gran/hertz/history", "pair_coeff * *", "run 0"],
                              ["coefficientFriction", "as requested by pair_style gran/hertz/history"]),
    "hist_stiffness_missing_kn": (base() + MATERIAL + ["pair_style gran/hooke/history/stiffness", "pair_coeff * *", "run 0"],
                                  ["Could not locate", "for kn as requested by pair_style gran/hooke/history/stiffness"]),
    "hist_stiffness_missing_gamman_abs": (base() + MATERIAL + ["fix k1 all property/global kn peratomtypepair 1 1e4",
                                                               "fix k2 all property/global kt peratomtypepair 1 1e4",
                                                               "pair_style gran/hooke/history/stiffness absolute_damping on",
                                                               "pair_coeff * *", "run 0"],
                                          ["for gamman_abs as requested by"]),
    "hist_hertz_stiffness_absolute_damping": (base() + MATERIAL + ["pair_style gran/hertz/history/stiffness absolute_damping on"],
                                              ["'absolute_damping' is not available with hertz stiffness"]),
    "hist_unknown_keyword": (base() + MATERIAL + ["pair_style gran/hertz/history tangential_dumping off"],
                             ["pair_style gran/hertz/history", "unknown keyword 'tangential_dumping'"]),
    "lammps_negative_stiffness": (base() + ["pair_style gran/hooke/history -2000 NULL 50 NULL 0.5 1"],
                                  ["pair_style gran/hooke/history", "must be >= 0"]),
    "lammps_bad_dampflag": (base() + ["pair_style gran/hertz/history 2000 NULL 50 NULL 0.5 2"],
                            ["dampflag must be 0 or 1, got '2'"]),
    "lammps_too_few_args": (base() + ["pair_style gran/hooke 2000 NULL 50"],
                            ["expected 'Kn Kt gamma_n gamma_t xmu dampflag"]),
    "x3_wrong_order": (base() + MATERIAL + ["pair_style gran model hertz rolling_friction cdt tangential history"],
                       ["wrong keyword order: 'tangential'"]),
    "x3_unknown_model": (base() + MATERIAL + ["pair_style gran model herz tangential history"],
                         ["unknown model 'herz'"]),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_input_gives_error(name):
    lines, expected = CASES[name]
    msg = run_deck(lines)
    assert msg is not None, f"{name}: no ERROR raised"
    assert msg.startswith("ERROR"), msg
    for part in expected:
        assert part in msg, f"{name}: {part!r} not in {msg!r}"


def test_good_deck_runs():
    assert run_deck(GOOD) is None
