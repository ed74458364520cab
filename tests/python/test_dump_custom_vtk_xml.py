"""dump custom/vtk with XML file names (.vtp .vtu .pvtp .pvtu) and the .pvd collection: every file parses as
XML (xml.etree), every array equals the legacy .vtk frame written by the same run, the .pvd lists each frame
with its time; and LIGGGHTS 3.8 run live on the same deck (three falling particles) writes the same set of
file names with the same arrays (names, types, components) and the same values, bit for bit."""
import struct
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from dembridge import read_vtk_particles
from dembridge.liggghts_deck import translate_text

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "oracle"))
import oracle_harness as oh  # noqa: E402

from vtk_reader import read_legacy  # noqa: E402

ATTRS = "id type x y z vx vy vz fx fy fz omegax omegay omegaz radius mass"
NAMES = {"vtk": "c_*.vtk", "vtp": "a_*.vtp", "vtu": "b_*.vtu", "pvtp": "d_*.pvtp", "pvtu": "e_*.pvtu"}
DT, EVERY, STEPS = 1e-5, 10, 20

DECK = f"""atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box
create_box 1 box
create_atoms 1 single 0.01 -0.01 0.0045 units box
create_atoms 1 single -0.01 0.01 0.0045 units box
create_atoms 1 single 0.0 0.0 0.0135 units box
set group all diameter 0.01 density 2500
velocity all set 0.3 0.0 -1.0
fix m1 all property/global youngsModulus peratomtype 5.e7
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7
fix m4 all property/global coefficientFriction peratomtypepair 1 0.3
pair_style gran model hertz tangential history
pair_coeff * *
neigh_modify delay 0
timestep {DT}
fix integr all nve/sphere
fix gravi all gravity 9.81 vector 0.0 0.0 -1.0
dump d all custom {EVERY} dump.txt id x y z
""" + "".join(f"dump v{k} all custom/vtk {EVERY} {name} {ATTRS}\n" for k, name in NAMES.items()) + f"run {STEPS}\n"


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def xml_arrays(path, piece_tag):
    """{name: (type, components, [values])} of a serial XML file's point data, and its Float32 points."""
    root = ET.parse(path).getroot()
    piece = root.find(f"{piece_tag}/Piece")
    assert piece is not None, path

    def values(e):
        conv = float if e.get("type").startswith("Float") else int
        return [conv(v) for v in (e.text or "").split()]
    arrays = {e.get("Name"): (e.get("type"), int(e.get("NumberOfComponents", "1")), values(e))
              for e in piece.find("PointData")}
    pts = piece.find("Points/DataArray")
    assert pts.get("type") == "Float32" and pts.get("NumberOfComponents") == "3"
    n = int(piece.get("NumberOfPoints"))
    cells = {e.get("Name"): values(e) for e in piece.find("Cells" if piece_tag == "UnstructuredGrid" else "Verts")}
    assert cells["connectivity"] == list(range(n)) and cells["offsets"] == list(range(1, n + 1))
    if piece_tag == "UnstructuredGrid":
        assert cells["types"] == [1] * n and int(piece.get("NumberOfCells")) == n  # VTK_VERTEX
    else:
        assert int(piece.get("NumberOfVerts")) == n
    return arrays, values(pts)


def box_of(path):
    root = ET.parse(path).getroot()
    assert root.get("type") == "RectilinearGrid"
    return [[float(v) for v in e.text.split()] for e in root.find("RectilinearGrid/Piece/Coordinates")]


def parallel_header(path, kind):
    """The piece file a .pvtp/.pvtu names, and its {name: (type, components)}."""
    root = ET.parse(path).getroot()
    assert root.get("type") == kind
    p = root.find(kind)
    pieces = [e.get("Source") for e in p.findall("Piece")]
    assert len(pieces) == 1
    return pieces[0], {e.get("Name"): (e.get("type"), int(e.get("NumberOfComponents", "1"))) for e in p.find("PPointData")}


def run_ours(tmp_path, nprocs=1):
    deck = f"plugin load {oh.plugin_path()}\n" + translate_text(DECK, "in.liggghts", notes=False).text
    wd = tmp_path / f"lammps{nprocs}"
    oh.run_lammps(deck, wd, nprocs=nprocs)
    return wd


def test_xml_frames_equal_the_legacy_frames_and_the_pvd_lists_them(tmp_path):
    wd = run_ours(tmp_path)
    steps = list(range(0, STEPS + 1, EVERY))
    for step in steps:
        legacy = read_legacy(wd / f"c_{step}.vtk")
        box = [read_legacy(wd / f"c_boundingBox_{step}.vtk")["coordinates"][a] for a in "XYZ"]
        for ext, tag in (("vtp", "PolyData"), ("vtu", "UnstructuredGrid"), ("pvtp", "PolyData"), ("pvtu", "UnstructuredGrid")):
            stem = NAMES[ext][0]
            frame = wd / f"{stem}_{step}.{ext}"
            if ext.startswith("p"):
                piece, declared = parallel_header(frame, "P" + tag)
                assert piece == f"{stem}_{step}_0.{ext[1:]}"
                arrays, points = xml_arrays(wd / piece, tag)
                assert declared == {k: (t, c) for k, (t, c, _) in arrays.items()}
                bpiece, _ = parallel_header(wd / f"{stem}_boundingBox_{step}.pvtr", "PRectilinearGrid")
                assert bpiece == f"{stem}_boundingBox_{step}_0.vtr" and box_of(wd / bpiece) == box
            else:
                arrays, points = xml_arrays(frame, tag)
                assert box_of(wd / f"{stem}_boundingBox_{step}.vtr") == box
            assert points == [f32(x) for p in legacy["points"] for x in p]  # the same floats
            assert list(arrays) == legacy["order"] == ["id", "type", "mass", "v", "f", "radius", "omega"]
            for name, (comps, typ, rows) in legacy["arrays"].items():
                t, c, vals = arrays[name]
                assert (t, c) == ({"int": "Int32", "double": "Float64"}[typ], comps), name
                assert vals == [x for r in rows for x in r], (step, ext, name)  # %.17g both: the same doubles
    assert legacy["arrays"]["v"][2][0][2] < -1.0  # gravity acted by the last frame
    # dembridge.read_vtk_particles reads every form alike (the points: the same floats)
    frames = {ext: read_vtk_particles(wd / f"{NAMES[ext][0]}_{STEPS}.{ext}") for ext in NAMES}
    for ext, f in frames.items():
        assert sorted(f) == sorted(frames["vtk"]), ext
        for k, v in f.items():
            want = frames["vtk"][k]
            if k == "points":
                v, want = v.astype(np.float32), want.astype(np.float32)
            assert v.shape == want.shape and (v == want).all(), (ext, k)
    for ext in ("vtp", "vtu", "pvtp", "pvtu"):
        stem = NAMES[ext][0]
        root = ET.parse(wd / f"{stem}.pvd").getroot()
        assert root.get("type") == "Collection"
        got = [(float(d.get("timestep")), d.get("file")) for d in root.find("Collection")]
        assert got == [(s * DT, f"{stem}_{s}.{ext}") for s in steps]
    assert not (wd / "c.pvd").exists() and (wd / "c.vtk.series").is_file()  # legacy frames: the JSON series


def test_file_names_and_arrays_as_liggghts_writes_them(tmp_path):
    ours = run_ours(tmp_path)
    ref = tmp_path / "liggghts"
    (tmp_path / "case").mkdir()
    oh.run_liggghts(tmp_path / "case", ref, deck_text=DECK)
    vtk_files = lambda d: sorted(p.name for p in d.iterdir() if p.suffix in (".vtp", ".vtu", ".pvtp", ".pvtu", ".vtr", ".pvtr"))
    # ours has the pieces its .pvtr headers name; LIGGGHTS's .pvtr is itself a serial grid and names none
    box_pieces = [f"{s}_boundingBox_{k}_0.vtr" for s in "de" for k in range(0, STEPS + 1, EVERY)]
    assert sorted(vtk_files(ref) + box_pieces) == vtk_files(ours)
    assert len(vtk_files(ref)) == 4 * 3 + 4 * 3 + 2 * 3  # frames, boxes, pieces of the parallel files
    for ext, tag in (("vtp", "PolyData"), ("vtu", "UnstructuredGrid")):
        stem = NAMES[ext][0]
        for step in range(0, STEPS + 1, EVERY):
            a, pa = xml_arrays(ref / f"{stem}_{step}.{ext}", tag)
            b, pb = xml_arrays(ours / f"{stem}_{step}.{ext}", tag)
            assert pa == pb, (ext, step)  # the float points
            # the same arrays in the same order, the same doubles (LIGGGHTS's XML files carry 17 digits)
            assert list(a.items()) == list(b.items()), (ext, step)
            assert box_of(ref / f"{stem}_boundingBox_{step}.vtr") == box_of(ours / f"{stem}_boundingBox_{step}.vtr")



@pytest.mark.two_cores
def test_two_ranks_write_the_same_files(tmp_path):
    """Rank 0 gathers the particles, sorted by ID: the XML files and the .pvd do not depend on the rank count."""
    one, two = run_ours(tmp_path, 1), run_ours(tmp_path, 2)
    names = sorted(p.name for p in one.iterdir() if p.suffix in (".vtp", ".vtu", ".pvtp", ".pvtu", ".vtr", ".pvtr", ".pvd"))
    assert len(names) == 4 * 3 * 2 + 2 * 3 * 2 + 4  # frames and boxes, the parallel files' pieces, the .pvd files
    assert names == sorted(p.name for p in two.iterdir() if p.suffix in (".vtp", ".vtu", ".pvtp", ".pvtu", ".vtr", ".pvtr", ".pvd"))
    for n in names:
        assert (one / n).read_bytes() == (two / n).read_bytes(), n
