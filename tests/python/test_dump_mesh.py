"""dump mesh/stl and dump mesh/vtk (LIGGGHTS's mesh output lines as LAMMPS dump styles) in-process:
which meshes a line writes, the '*' in file names, that they write what fix mesh/dump writes (one
writer), and bad input. The comparison with LIGGGHTS 3.8 itself is tests/oracle/test_mesh_dump_oracle.py."""
import os
import struct

from dembridge import ROOT

from test_mesh_fixes import deck_head, error_of, flat_nodes, read_stl_nodes, run

PLATE = os.path.join(ROOT, "tests", "data", "liggghts-walls", "mesh", "plate.stl")
PADDLE = os.path.join(ROOT, "tests", "data", "liggghts-walls", "mesh_move_rotate_paddle", "paddle.stl")
MESHES = [f"fix plate all mesh/surface/stress file {PLATE} type 1",
          f"fix pad all mesh/surface file {PADDLE} type 1 move 0 0 0.03",
          "fix turn all move/mesh mesh pad rotate origin 0 0 0.036 axis 1 0 0 period 0.004"]


def facets(path):
    return sum(1 for line in open(path) if line.split()[:1] == ["facet"])


def test_without_mesh_ids_all_meshes_defined_before_the_dump(tmp_path):
    late = f"fix late all mesh/surface file {PLATE} type 1 move 0 0 -0.01"
    run(deck_head() + MESHES + [f"dump all all mesh/stl 10 {tmp_path}/all*.stl",
                                f"dump one all mesh/stl 10 {tmp_path}/one*.stl pad",
                                f"dump v all mesh/vtk 10 {tmp_path}/v*.vtk area",
                                f"dump gone all mesh/stl 10 {tmp_path}/gone*.stl", "undump gone", late, "run 10"]).close()
    assert facets(tmp_path / "all10.stl") == 4  # plate + pad, not 'late' (LIGGGHTS: meshes at the dump line)
    assert facets(tmp_path / "one10.stl") == 2
    assert "POLYGONS 4 16" in (tmp_path / "v10.vtk").read_text()
    assert sorted(os.listdir(tmp_path)) == sorted(f"{p}{s}.{e}" for p, e in (("all", "stl"), ("one", "stl"), ("v", "vtk"))
                                                  for s in (0, 10))  # none from the undumped dump


def test_vtk_without_star_keeps_the_last_frame_and_stl_equals_fix_mesh_dump(tmp_path):
    """binary STL: the float32 of the ASCII file's (17-digit) vertices"""
    run(deck_head() + MESHES + [f"dump v all mesh/vtk 5 {tmp_path}/one.vtk vel pad",
                                f"dump s all mesh/stl 5 {tmp_path}/dump*.stl pad",
                                f"dump b all mesh/stl 5 {tmp_path}/bin*.stl pad binary",
                                f"fix f all mesh/dump 5 stl {tmp_path}/fix*.stl pad", "run 10"]).close()
    assert (tmp_path / "dump10.stl").read_text() == (tmp_path / "fix10.stl").read_text()
    nodes_10 = read_stl_nodes(tmp_path / "dump10.stl")
    text = (tmp_path / "one.vtk").read_text().split()
    i = text.index("POINTS")
    assert [float(c) for c in text[i + 3:i + 3 + 18]] == [c for p in nodes_10 for c in p]
    assert nodes_10 != read_stl_nodes(tmp_path / "dump5.stl")  # the paddle turned in between
    data = (tmp_path / "bin10.stl").read_bytes()
    assert struct.unpack_from("<I", data, 80) == (2,) and len(data) == 84 + 2 * 50
    floats = [c for k in range(2) for c in struct.unpack_from("<12f", data, 84 + 50 * k)[3:]]
    assert floats == [struct.unpack("<f", struct.pack("<f", c))[0] for c in flat_nodes(nodes_10)]


def test_bad_input_gives_errors_naming_the_dump_and_the_argument(tmp_path):
    f = f"{tmp_path}/m*.vtk"
    s = f"{tmp_path}/m*.stl"
    cases = {
        "unknown keyword": (f"dump v all mesh/vtk 10 {f} stress colour", ["dump mesh/vtk (id v)", "'colour'", "neither a keyword"]),
        "unknown mesh id": (f"dump s all mesh/stl 10 {s} nope", ["dump mesh/stl (id s)", "'nope'", "fix mesh/surface"]),
        "not a mesh": (f"dump s all mesh/stl 10 {s} integr", ["dump mesh/stl (id s)", "'integr' is a fix nve/sphere, not a mesh"]),
        "wear": (f"dump v all mesh/vtk 10 {f} wear plate", ["dump mesh/vtk (id v)", "keyword 'wear'", "not supported"]),
        "owner": (f"dump v all mesh/vtk 10 {f} owner", ["keyword 'owner'", "not supported"]),
        "temp": (f"dump v all mesh/vtk 10 {f} stress temp", ["keyword 'temp'", "not supported"]),
        "nothing selected": (f"dump v all mesh/vtk 10 {f} plate", ["dump mesh/vtk (id v)", "no dump quantity selected"]),
        "interpolate": (f"dump v all mesh/vtk 10 {f} output interpolate stress", ["'output interpolate'", "output face"]),
        "stl without star": (f"dump s all mesh/stl 10 {tmp_path}/m.stl", ["dump mesh/stl (id s)", "file", "'*'"]),
        "per-rank file": (f"dump v all mesh/vtk 10 {tmp_path}/m%.vtk stress", ["file", "'%'"]),
        "xml vtk": (f"dump v all mesh/vtk 10 {tmp_path}/m*.vtp stress", ["file", ".vtk"]),
        "ghost": (f"dump s all mesh/stl 10 {s} ghost", ["keyword 'ghost'"]),
        # N is read by LAMMPS's Output before the style exists: its ERROR and the "Last input line"
        "zero interval": (f"dump s all mesh/stl 0 {s}", ["Invalid dump frequency 0", "dump s all mesh/stl 0"]),
        "bad interval": (f"dump s all mesh/stl ten {s}", ["'ten'", "dump s all mesh/stl ten"]),
    }
    for name, (line, needles) in cases.items():
        msg = error_of(deck_head() + MESHES + [line])
        assert msg is not None, name
        for n in needles:
            assert n in msg, f"{name}: '{n}' not in: {msg}"
    msg = error_of(deck_head() + MESHES + [f"dump s all mesh/stl 10 {s} pad", "unfix turn", "unfix pad", "run 1"])
    assert msg is not None and "dump mesh/stl (id s)" in msg and "'pad' does not exist" in msg
