"""wear finnie of fix mesh/surface/stress, written by dump mesh/vtk ... wear: Finnie's formula on one
contact (a sphere held against a flat plate at a fixed speed, so every step adds the same wear), and
LIGGGHTS 3.8 run live on tests/data/liggghts-wear (200 particles falling into a funnel). LIGGGHTS's
values at full precision come from its XML mesh dump (.vtp) and its binary restart file
(liggghts_restart.py): its legacy mesh dump prints 11 significant digits only."""
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from dembridge import new_lammps

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "oracle"))
import oracle_harness as oh  # noqa: E402

from bad_input_check import assert_error  # noqa: E402
from liggghts_restart import wear_by_triangle  # noqa: E402
from test_bad_input import run_deck  # noqa: E402

PLATE = ROOT / "tests" / "data" / "liggghts-walls" / "mesh" / "plate.stl"  # two triangles, z = 0, area 8e-4 each
FUNNEL = ROOT / "tests" / "data" / "liggghts-walls" / "hopper200_funnel_settle"  # data.txt, funnel.stl
CASE = ROOT / "tests" / "data" / "liggghts-wear"
K, DT, N = 2.5, 1e-6, 50


def read_wear(path):
    """Cell array 'wear' of a legacy VTK file: ours (SCALARS wear double 1 / LOOKUP_TABLE default) or
    LIGGGHTS's VTK 5.1 field data (wear 1 NCELLS double)."""
    tok = Path(path).read_text().split()
    i = tok.index("wear")
    if tok[i - 1] == "SCALARS":
        n = int(tok[tok.index("CELL_DATA") + 1])
        return [float(v) for v in tok[i + 5:i + 5 + n]]
    n = int(tok[i + 2])
    return [float(v) for v in tok[i + 4:i + 4 + n]]


def plate_lines(v, vtk_style, dump_dir):
    """The plate deck (LAMMPS syntax; the LIGGGHTS one differs in the lines liggghts_deck rewrites)."""
    return ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f", "newton off", "comm_modify vel yes",
            "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box", "create_box 1 box",
            "create_atoms 1 single 0.01 -0.01 0.0045 units box", "set group all diameter 0.01 density 2500",
            f"velocity all set {v[0]} {v[1]} {v[2]}",
            "fix m1 all property/global youngsModulus peratomtype 5.e7",
            "fix m2 all property/global poissonsRatio peratomtype 0.3",
            "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
            "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
            f"fix m6 all property/global k_finnie peratomtypepair 1 {K}",
            "pair_style gran model hertz tangential history", "pair_coeff * *", f"timestep {DT}",
            f"fix cad all mesh/surface/stress file {PLATE} type 1 wear finnie",
            "fix walls all wall/gran model hertz tangential no_history mesh n_meshes 1 meshes cad",
            f"dump d all custom {N} {dump_dir}/dump.txt id x y z",
            f"dump w all mesh/{vtk_style} {N} {dump_dir}/wear_*.vtk wear cad", f"run {N}"]


def plate_run(tmp_path, v):
    """Our wear after N steps and |F| of the contact (no integrator: the sphere keeps x and v)."""
    lmp = new_lammps()
    for c in plate_lines(v, "vtk", tmp_path):
        lmp.command(c)
    f = [lmp.extract_fix("cad", 0, 1, k) for k in range(3)]  # total force on the mesh = -contact force
    lmp.close()
    return read_wear(tmp_path / f"wear_{N}.vtk"), math.sqrt(sum(x * x for x in f))


def plate_liggghts(tmp_path, v):
    """LIGGGHTS 3.8's wear on the same deck (atom_style granular, communicate, mesh/gran/VTK): the values of
    its restart file written after the run, checked against its own 11-digit mesh dump."""
    lines = ["atom_style granular" if l == "atom_style sphere" else "communicate single vel yes" if l.startswith("comm_modify")
             else l for l in plate_lines(v, "gran/VTK", tmp_path / "lig")] + ["write_restart wear.restart"]
    (tmp_path / "case").mkdir()
    oh.run_liggghts(tmp_path / "case", tmp_path / "lig", deck_text="\n".join(lines) + "\n")
    full = wear_by_triangle(tmp_path / "lig" / "wear.restart", "cad")
    assert sorted(full) == [0, 1]
    printed = read_wear(tmp_path / "lig" / f"wear_{N}.vtk")
    for t, x in enumerate(printed):
        assert abs(full[t] - x) <= 5e-11 * abs(full[t]), (t, full[t], x)  # the restart holds what the dump rounds
    return [full[0], full[1]]


def finnie(v, fmag, area):
    """2 k |v| |F| f(gamma) dt / A per step; gamma between v and the plate (normal z)."""
    speed = math.sqrt(sum(x * x for x in v))
    s, c = abs(v[2]) / speed, math.hypot(v[0], v[1]) / speed
    f = 0.33333 * c * c if (c < 0.001 or 3 * s > c) else 2 * s * c - 3 * s * s
    return 2 * K * speed * fmag * f * DT / area


@pytest.mark.parametrize("v,branch", [((0.3, 0.0, -1.0), "steep"), ((1.0, 0.2, -0.2), "shallow"), ((0.0, 0.0, -0.5), "head-on")])
def test_finnie_formula_on_one_contact(tmp_path, v, branch):
    """Every step adds 2 k |v| |F| f(gamma) dt / A (none for the setup forces, as in LIGGGHTS); head-on
    (gamma = 90 degrees) Finnie's f is cos^2/3 = 0. LIGGGHTS 3.8 on the same deck, to its 11 printed digits."""
    wear, fmag = plate_run(tmp_path, v)
    assert fmag > 0
    expect = N * finnie(v, fmag, 8e-4)
    assert abs(wear[0] - expect) <= 1e-12 * expect, (branch, wear[0], expect)
    assert (expect > 0) == (branch != "head-on")
    assert wear[1] == 0.0  # the other triangle is not touched
    lig = plate_liggghts(tmp_path, v)
    assert lig == wear, (lig, wear)


def test_no_wear_when_moving_away(tmp_path):
    wear, fmag = plate_run(tmp_path, (0.5, 0.0, 0.3))
    assert fmag > 0 and wear == [0.0, 0.0]


def read_wear_vtp(path):
    """Cell array 'wear' of a VTK XML PolyData mesh file (LIGGGHTS 3.8's dump mesh/vtk ... .vtp writes 17 digits)."""
    cells = ET.parse(path).getroot().find("PolyData/Piece/CellData")
    return [float(v) for v in next(e for e in cells if e.get("Name") == "wear").text.split()]


def test_wear_deck_against_liggghts(tmp_path):
    """Every triangle's wear at steps 0, 7000 and 14000: to LIGGGHTS's 11 printed digits in the legacy mesh dumps,
    and to 1e-12 in the XML ones (a second mesh dump with a .vtp name, which LIGGGHTS writes with 17 digits);
    at the end also against the doubles of LIGGGHTS's restart file written after the run."""
    xml_dump = "dump wx all mesh/vtk 7000 mesh_*.vtp wear cad\n"
    deck = (CASE / "in.liggghts").read_text().replace("run             14000", xml_dump + "run             14000")
    assert xml_dump in deck
    ref = tmp_path / "liggghts"
    oh.run_liggghts(FUNNEL, ref, deck_text=deck + "write_restart wear.restart\n")
    ours = tmp_path / "lammps"
    lmp_deck = oh.liggghts_to_lammps_deck(deck.replace("mesh/gran/VTK", "mesh/vtk"), syntax="3x")
    oh.run_lammps(lmp_deck, ours, files=[FUNNEL / "data.txt", FUNNEL / "funnel.stl"])
    worn, worst, same = 0, 0.0, 0
    for step in (0, 7000, 14000):
        a, b = read_wear(ref / f"mesh_{step}.vtk"), read_wear(ours / f"mesh_{step}.vtk")
        assert len(a) == len(b) == 60
        for t, (x, y) in enumerate(zip(a, b)):
            # LIGGGHTS prints 11 significant digits: a half unit of the last one is <= 5e-11 relative
            assert abs(x - y) <= 5e-11 * abs(x) + 1e-12 * abs(y), (step, t, x, y)
            assert (x == 0.0) == (y == 0.0), (step, t, x, y)
        worn = sum(1 for x in a if x > 0)
        full, got = read_wear_vtp(ref / f"mesh_{step}.vtp"), read_wear_vtp(ours / f"mesh_{step}.vtp")
        assert got == b and len(full) == 60  # our XML frame holds our legacy frame's doubles
        for t, (x, y) in enumerate(zip(full, got)):
            assert abs(x - y) <= 1e-12 * abs(x), (step, t, x, y)
            worst = max(worst, abs(x - y) / abs(x)) if x else worst
            same += x == y and x > 0
    assert worn >= 20  # the funnel did wear (34 of 60 triangles by step 14000)
    restart = wear_by_triangle(ref / "wear.restart", "cad")
    assert [restart[t] for t in range(60)] == full  # two readouts of LIGGGHTS's doubles agree
    print(f"wear at steps 7000 and 14000: largest relative difference {worst:.3g}; {same} of the worn triangle-frames "
          f"bit-identical ({worn} worn at the end)")

BASE = ["units si", "atom_style sphere", "boundary f f f", "newton off", "comm_modify vel yes", "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05",
        "create_box 1 box", "create_atoms 1 single 0.01 -0.01 0.0045 units box", "set group all diameter 0.01 density 2500",
        "fix m1 all property/global youngsModulus peratomtype 5.e7", "fix m2 all property/global poissonsRatio peratomtype 0.3",
        "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
        "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
        "pair_style gran model hertz tangential history", "pair_coeff * *", "timestep 1e-6"]
MESH = f"fix cad all mesh/surface/stress file {PLATE} type 1"
WALL = "fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes cad"
KF = "fix m6 all property/global k_finnie peratomtypepair 1 1.0"
BAD = {
    "wear_word": (BASE + [MESH + " wear yes"], ["fix mesh/surface/stress (id cad)", "wear", "expected 'finnie' or 'off'"]),
    "wear_without_stress": (BASE + [MESH + " stress off wear finnie"], ["(id cad)", "wear finnie", "stress on"]),
    "wear_on_plain_mesh": (BASE + [f"fix cad all mesh/surface file {PLATE} type 1 wear finnie"], ["wear", "mesh/surface/stress"]),
    "no_k_finnie": (BASE + [MESH + " wear finnie", WALL, "run 0"], ["k_finnie", "(id cad) wear finnie"]),
    "k_finnie_per_type": (BASE + ["fix m6 all property/global k_finnie peratomtype 1.0", MESH + " wear finnie", WALL, "run 0"],
                          ["k_finnie", "peratomtypepair style required", "wear finnie"]),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_wear_bad_input(name):
    assert_error(name, *BAD[name])


def test_wear_good_deck_runs():
    assert run_deck(BASE + [KF, MESH + " wear finnie", WALL, "run 5"]) is None
