"""fix wall/gran and compute wall/gran/local: bad input gets a LAMMPS ERROR naming the command, the
argument and what was expected (issue 10, deliverable 7). One fresh LAMMPS instance per case."""
import os

import pytest

from test_bad_input import run_deck  # one fresh LAMMPS per deck, returns the ERROR text

MATERIAL = [
    "fix m1 all property/global youngsModulus peratomtype 5.e7",
    "fix m2 all property/global poissonsRatio peratomtype 0.3",
    "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
    "fix m5 all property/global characteristicVelocity scalar 1.0",
]


def base(atom_style="sphere", units="si"):
    lines = [f"units {units}", f"atom_style {atom_style}", "boundary f f f", "newton off", "comm_modify vel yes",
             "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05", "create_box 1 box",
             "create_atoms 1 single 0.001 0.002 0.004 units box"]
    if atom_style == "sphere":
        lines.append("set group all diameter 0.01 density 2500")
    return lines


def wall(args, extra=()):
    return base() + MATERIAL + ["pair_style gran model hertz tangential history", "pair_coeff * *", "timestep 1e-6",
                                "fix w all wall/gran " + args, *extra, "fix i all nve/sphere", "run 2"]


W = "model hertz tangential history "
PLATE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "liggghts-walls", "mesh", "plate.stl")


def on_plate(x, y, z=0.0, meshes="n_meshes 1 meshes cad"):
    """the atom's centre at (x, y, z) over plate.stl (z = 0, two triangles, diagonal x = y; radius 0.005)"""
    return base() + MATERIAL + ["pair_style gran model hertz tangential history", "pair_coeff * *", "timestep 1e-6",
                                f"set atom 1 x {x} y {y} z {z}", f"fix cad all mesh/surface file {PLATE} type 1",
                                "fix w all wall/gran " + W + "mesh " + meshes, "fix i all nve/sphere", "run 2"]
CASES = {
    "unknown_shape": (wall(W + "primitive type 1 wplane 0"), ["fix w wall/gran", "unknown primitive wall 'wplane'"]),
    "position_not_a_number": (wall(W + "primitive type 1 zplane abc"), ["fix w wall/gran", "expected a number", "'abc'"]),
    "type_not_integer": (wall(W + "primitive type one zplane 0"), ["expected an integer", "'one'"]),
    "type_out_of_range": (wall(W + "primitive type 2 zplane 0"), ["fix w wall/gran", "primitive type 2", "1 <= type <= max type"]),
    "cylinder_radius_zero": (wall(W + "primitive type 1 zcylinder 0 0 0"), ["zcylinder", "must be > 0"]),
    "cylinder_missing_centre": (wall(W + "primitive type 1 zcylinder 0.02 0"), ["missing", "second axis coordinate"]),
    "no_wall": (wall(W.strip()), ["fix w wall/gran", "no wall given"]),
    "two_primitives": (wall(W + "primitive type 1 zplane 0 primitive type 1 xplane 0"), ["'primitive' given together with another"]),
    "primitive_then_mesh": (wall(W + "primitive type 1 zplane 0 mesh n_meshes 1 meshes cad"), ["'mesh' given together with 'primitive'"]),
    "mesh_then_primitive": (wall(W + "mesh n_meshes 1 meshes cad primitive type 1 zplane 0"), ["'primitive' given together with 'mesh'"]),
    "meshes_before_n_meshes": (wall(W + "mesh meshes cad"), ["have to define 'n_meshes' before 'meshes'"]),
    "too_few_meshes": (wall(W + "mesh n_meshes 2 meshes cad"), ["'meshes' expects 2 mesh fix IDs"]),
    # a centre exactly on the wall: no contact normal (LIGGGHTS 3.8 computes NaN forces at step 0)
    "centre_on_plane": (wall(W + "primitive type 1 zplane 0.004"),
                        ["fix w wall/gran", "atom 1 at (0.001 0.002 0.0040000000000000001)", "has its centre on the zplane at 0.004",
                         "contact normal is undefined"]),
    "centre_in_mesh_face": (on_plate(0.001, 0.002), ["fix w wall/gran", "atom 1", "centre on triangle", "of mesh cad",
                                                    "contact normal is undefined"]),
    "centre_on_mesh_edge": (on_plate(0.01, -0.02), ["fix w wall/gran", "atom 1 at (0.01 -0.02 0)", "centre on triangle 1 (file order) of mesh cad",
                                                   "contact normal is undefined"]),
    "mesh_listed_twice": (on_plate(0.001, 0.002, 0.004, "n_meshes 2 meshes cad cad"), ["fix w wall/gran", "mesh 'cad' is listed twice in 'meshes'",
                                                                     "double its wall force"]),
    "unknown_model": (wall("model hooky tangential history primitive type 1 zplane 0"), ["fix w wall/gran", "unknown model 'hooky'"]),
    "bad_tangential": (wall("model hertz tangential histor primitive type 1 zplane 0"), ["fix w wall/gran", "'histor'"]),
    "missing_model": (wall("primitive type 1 zplane 0"), ["fix w wall/gran", "expected 'model"]),
    "unknown_keyword": (wall(W + "primitive type 1 zplane 0 wiggle x 1 1"), ["fix w wall/gran", "'wiggle'"]),
    "shear_bad_dim": (wall(W + "primitive type 1 zplane 0 shear w 1"), ["'shear' expects x, y or z", "'w'"]),
    "shear_on_mesh": (wall(W + "mesh n_meshes 1 meshes cad shear x 1"), ["'shear' is only available for primitive walls"]),
    "store_force_yes": (wall(W + "primitive type 1 zplane 0 store_force yes"), ["'store_force yes' is not supported"]),
    "unsupported_keyword": (wall(W + "primitive type 1 zplane 0 track_energy"), ["keyword 'track_energy' is not supported"]),
    "legacy_bad_rolling": (base() + MATERIAL + ["pair_style gran/hertz/history", "pair_coeff * *",
                                                "fix w all wall/gran/hertz/history primitive type 1 zplane 0 rolling_friction eps"],
                           ["fix w wall/gran/hertz/history", "rolling_friction expects", "'eps'"]),
    "legacy_epsd_without_history": (base() + MATERIAL + ["pair_style gran/hooke", "pair_coeff * *",
                                                         "fix w all wall/gran/hooke primitive type 1 zplane 0 rolling_friction epsd"],
                                    ["fix w wall/gran/hooke", "needs per-contact history"]),
    "missing_material": (base() + MATERIAL[:3] + MATERIAL[4:] + ["pair_style gran model hertz", "pair_coeff * *",
                                                                 "fix w all wall/gran " + W + "primitive type 1 zplane 0", "run 1"],
                         ["coefficientFriction"]),
    "not_sphere": (base(atom_style="atomic") + ["fix w all wall/gran " + W + "primitive type 1 zplane 0"],
                   ["fix w wall/gran", "atom style sphere"]),
    "units_real": (base(units="real") + MATERIAL + ["pair_style zero 1.0", "pair_coeff * *",
                                                   "fix w all wall/gran " + W + "primitive type 1 zplane 0", "run 1"],
                   ["fix w wall/gran", "non-consistent unit system 'real'"]),
    "particle_on_cylinder_axis": (wall(W + "primitive type 1 zcylinder 0.02 0.001 0.002"), ["fix w wall/gran", "atom 1", "cylinder axis"]),
    # LAMMPS syntax: the built-in fix reports (its own message)
    "lammps_syntax_goes_to_builtin": (wall("hooke 2500 NULL"), ["classic gran model", "fix w all wall/gran hooke"]),
    "compute_unknown_fix": (wall(W + "primitive type 1 zplane 0", extra=["compute c all wall/gran/local nowall"]),
                            ["compute c wall/gran/local", "no fix with ID 'nowall'"]),
    "compute_not_a_wall": (wall(W + "primitive type 1 zplane 0")[:-2] + ["fix i0 all nve/sphere", "compute c all wall/gran/local i0"],
                           ["compute c wall/gran/local", "not a dembridge fix wall/gran"]),
    "compute_no_argument": (wall(W + "primitive type 1 zplane 0", extra=["compute c all wall/gran/local"]),
                            ["compute c wall/gran/local", "expected exactly one argument"]),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_wall_input(name):
    lines, fragments = CASES[name]
    msg = run_deck(lines)
    assert msg is not None, f"{name}: no error"
    for frag in fragments:
        assert frag in msg, f"{name}: '{frag}' not in error message: {msg}"


def test_good_wall_deck_runs():
    assert run_deck(wall(W + "primitive type 1 zplane 0", extra=["compute c all wall/gran/local w"])) is None
