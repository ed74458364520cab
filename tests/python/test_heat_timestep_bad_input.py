"""Bad input to fix heat/gran, LIGGGHTS's fix property/atom, fix check/timestep/gran and the pair
style's model settings: each a LAMMPS ERROR naming the command, the argument and what was expected.
Also: 'error yes' turns check/timestep/gran's warning into an ERROR with LIGGGHTS's text."""
import pytest

from bad_input_check import assert_error
from test_bad_input import run_deck  # fresh LAMMPS, returns the ERROR text or None

BASE = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f", "newton off", "comm_modify vel yes",
        "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05", "create_box 1 box",
        "create_atoms 1 single -0.0049 0 0 units box", "create_atoms 1 single 0.0049 0 0 units box",
        "set group all diameter 0.01 density 2500",
        "fix m1 all property/global youngsModulus peratomtype 5.e7",
        "fix m2 all property/global poissonsRatio peratomtype 0.3",
        "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
        "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3"]
PAIR = ["pair_style gran model hertz tangential history", "pair_coeff * *", "timestep 1e-6"]
THERMAL = ["fix k all property/global thermalConductivity peratomtype 10.",
           "fix c all property/global thermalCapacity peratomtype 100."]
GOOD = BASE + PAIR + THERMAL


H = "fix h all heat/gran"
P = "fix t all property/atom"
T = "fix ts all check/timestep/gran"
CASES = {
    "heat_no_args": (GOOD + [H], ["fix h heat/gran", "'initial_temperature'", "missing"]),
    "heat_wrong_keyword": (GOOD + [H + " T0 300"], ["fix h heat/gran", "'T0'", "expected keyword 'initial_temperature'"]),
    "heat_t0_not_number": (GOOD + [H + " initial_temperature hot"], ["fix h heat/gran", "initial_temperature", "'hot'"]),
    "heat_area_mode": (GOOD + [H + " initial_temperature 300 contact_area sphere"], ["contact_area", "'sphere'", "overlap"]),
    "heat_area_constant_negative": (GOOD + [H + " initial_temperature 300 contact_area constant -1"],
                                    ["fix h heat/gran", "contact_area constant", "positive"]),
    "heat_area_correction": (GOOD + [H + " initial_temperature 300 area_correction yes"], ["area_correction", "not implemented"]),
    "heat_unknown_keyword": (GOOD + [H + " initial_temperature 300 radiation on"], ["fix h heat/gran", "'radiation'", "unknown keyword"]),
    "heat_no_conductivity": (BASE + PAIR + [THERMAL[1], H + " initial_temperature 300", "run 0"],
                             ["thermalConductivity", "fix h heat/gran", "property/global thermalConductivity"]),
    "heat_no_capacity": (BASE + PAIR + [THERMAL[0], H + " initial_temperature 300", "run 0"],
                         ["thermalCapacity", "fix h heat/gran"]),
    "heat_negative_conductivity": (BASE + PAIR + ["fix k all property/global thermalConductivity peratomtype -1.", THERMAL[1],
                                                  H + " initial_temperature 300", "run 0"],
                                   ["fix h heat/gran", "thermalConductivity of type 1", "< 0"]),
    "heat_conductivity_scalar": (BASE + PAIR + ["fix k all property/global thermalConductivity scalar 1.", THERMAL[1],
                                                H + " initial_temperature 300", "run 0"],
                                 ["thermalConductivity", "peratomtype style required", "fix h heat/gran"]),
    "heat_not_a_gran_pair": (BASE + ["pair_style zero 0.02", "pair_coeff * *"] + THERMAL + [H + " initial_temperature 300", "run 0"],
                             ["fix h heat/gran", "granular pair style"]),
    "heat_needs_sphere": (["units si", "atom_style atomic", "region box block 0 1 0 1 0 1", "create_box 1 box",
                           H + " initial_temperature 300"], ["fix h heat/gran", "radius and mass"]),
    "propatom_restart_word": (GOOD + [P + " Temp scalar maybe no no 1."], ["fix t property/atom", "restart", "'maybe'"]),
    "propatom_no_default": (GOOD + [P + " Temp scalar yes no no"], ["fix t property/atom", "default value", "missing"]),
    "propatom_two_defaults": (GOOD + [P + " Temp scalar yes no no 1. 2."], ["fix t property/atom", "one default value, got 2"]),
    "propatom_default_not_number": (GOOD + [P + " Temp scalar yes no no warm"], ["fix t property/atom", "default value", "'warm'"]),
    "propatom_prefixed_name": (GOOD + [P + " d_Temp scalar yes no no 1."], ["fix t property/atom", "'d_Temp'", "no i_/d_ prefix"]),
    "propatom_twice": (GOOD + [P + " Temp scalar yes no no 1.", "fix t2 all property/atom Temp scalar yes no no 1."],
                       ["fix t2 property/atom", "'Temp'", "exists already"]),
    "ts_missing_hertz": (GOOD + [T + " 100 0.1"], ["check/timestep/gran (id ts)", "fraction_hertz", "missing"]),
    "ts_zero_every": (GOOD + [T + " 0 0.1 0.1"], ["check/timestep/gran (id ts)", "N", "positive"]),
    "ts_negative_rayleigh": (GOOD + [T + " 100 -0.1 0.1"], ["check/timestep/gran (id ts)", "fraction_rayleigh", "positive"]),
    "ts_warn_word": (GOOD + [T + " 100 0.1 0.1 warn maybe"], ["check/timestep/gran (id ts)", "warn", "'maybe'"]),
    "ts_unknown_keyword": (GOOD + [T + " 100 0.1 0.1 loud yes"], ["check/timestep/gran (id ts)", "'loud'", "unknown keyword"]),
    "ts_negative_vmax": (GOOD + [T + " 100 0.1 0.1 vmax -2"], ["check/timestep/gran (id ts)", "vmax", ">= 0"]),
    "ts_not_a_gran_pair": (BASE + ["pair_style zero 0.02", "pair_coeff * *", T + " 10 0.1 0.1", "run 0"],
                           ["check/timestep/gran (id ts)", "granular pair style"]),
    "pair_hertz_viscous": (BASE + ["pair_style gran model hertz tangential history viscous on"],
                           ["pair_style gran", "model hertz has no viscous model", "model hooke"]),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_input(name):
    assert_error(name, *CASES[name])


def test_good_deck_runs():
    assert run_deck(GOOD + [H + " initial_temperature 300", T + " 10 0.1 0.1", "fix i all nve/sphere", "run 20"]) is None


def test_error_yes_stops_with_liggghts_text():
    """dt = 5e-5 s is ~7 % of these spheres' Rayleigh time (limit 1 %)."""
    msg = run_deck(BASE + ["pair_style gran model hertz tangential history", "pair_coeff * *", "timestep 5e-5",
                           T + " 10 0.01 0.5 error yes", "fix i all nve/sphere", "run 20"])
    assert msg is not None and "Fix check/timestep/gran (id ts): time-step is" in msg and "% of rayleigh time" in msg, msg
