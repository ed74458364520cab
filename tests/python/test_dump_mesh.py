"""dump mesh/stl and dump mesh/vtk (LIGGGHTS's mesh output lines as LAMMPS dump styles) in-process:
which meshes a line writes, the '*' in file names, that they write what fix mesh/dump writes (one
writer), and bad input. The comparison with LIGGGHTS 3.8 itself is tests/oracle/test_mesh_dump_oracle.py."""
import math
import os
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

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
    # and what it writes is the moved paddle: the input file's nodes shifted by `move`, turned by the
    # closed-form angle 2 pi t / period about the x axis through (0, 0, 0.036) after 10 steps of 1e-6 s
    th = 2 * math.pi * 10e-6 / 0.004
    expected = [(x, 0.0 + math.cos(th) * y - math.sin(th) * (z + 0.03 - 0.036),
                 0.036 + math.sin(th) * y + math.cos(th) * (z + 0.03 - 0.036)) for x, y, z in read_stl_nodes(PADDLE)]
    assert len(nodes_10) == len(expected) == 6
    assert max(abs(a - b) for p, q in zip(nodes_10, expected) for a, b in zip(p, q)) < 1e-15
    text = (tmp_path / "one.vtk").read_text().split()
    i = text.index("POINTS")
    assert [float(c) for c in text[i + 3:i + 3 + 18]] == [c for p in nodes_10 for c in p]
    assert nodes_10 != read_stl_nodes(tmp_path / "dump5.stl")  # the paddle turned in between
    data = (tmp_path / "bin10.stl").read_bytes()
    assert struct.unpack_from("<I", data, 80) == (2,) and len(data) == 84 + 2 * 50
    floats = [c for k in range(2) for c in struct.unpack_from("<12f", data, 84 + 50 * k)[3:]]
    assert floats == [struct.unpack("<f", struct.pack("<f", c))[0] for c in flat_nodes(nodes_10)]


def legacy_mesh_arrays(path):
    """{name: flat values} of our legacy mesh file's CELL_DATA / POINT_DATA, and its points."""
    tok = open(path).read().split()
    i = tok.index("POINTS")
    n = int(tok[i + 1])
    points = [float(v) for v in tok[i + 3:i + 3 + 3 * n]]
    out, k = {}, i + 3 + 3 * n
    while k < len(tok):
        if tok[k] in ("CELL_DATA", "POINT_DATA"):
            count, k = int(tok[k + 1]), k + 2
        elif tok[k] == "SCALARS":
            out[tok[k + 1]], k = [float(v) for v in tok[k + 6:k + 6 + count]], k + 6 + count
        elif tok[k] in ("VECTORS", "NORMALS"):
            out[tok[k + 1]], k = [float(v) for v in tok[k + 3:k + 3 + 3 * count]], k + 3 + 3 * count
        else:
            k += 1
    return out, points


def test_vtp_holds_the_legacy_arrays_and_the_pvd_lists_the_frames(tmp_path):
    """A .vtp name: VTK XML PolyData (parsed here with xml.etree) with the legacy file's points and arrays,
    and mesh.pvd listing each frame with its time."""
    fields = "stress stresscomponents id vel wear area aedges acorners"
    run(deck_head() + MESHES + [f"dump v all mesh/vtk 5 {tmp_path}/m_*.vtk {fields}",
                                f"dump x all mesh/vtk 5 {tmp_path}/m_*.vtp {fields}", "run 10"]).close()
    for step in (0, 5, 10):
        legacy, points = legacy_mesh_arrays(tmp_path / f"m_{step}.vtk")
        piece = ET.parse(tmp_path / f"m_{step}.vtp").getroot().find("PolyData/Piece")
        assert piece.get("NumberOfPoints") == "12" and piece.get("NumberOfPolys") == "4"
        vals = lambda e: [float(v) for v in (e.text or "").split()]
        assert vals(piece.find("Points/DataArray")) == points
        polys = {e.get("Name"): vals(e) for e in piece.find("Polys")}
        assert polys == {"connectivity": list(range(12)), "offsets": [3, 6, 9, 12]}
        got = {e.get("Name"): vals(e) for e in piece.find("CellData")}
        got.update({e.get("Name"): vals(e) for e in piece.find("PointData")})
        assert got == legacy and len(got) >= 9, (step, sorted(got))
    root = ET.parse(tmp_path / "m.pvd").getroot()
    assert [(float(d.get("timestep")), d.get("file")) for d in root.find("Collection")] == \
        [(s * 1e-6, f"m_{s}.vtp") for s in (0, 5, 10)]


def test_bad_input_gives_errors_naming_the_dump_and_the_argument(tmp_path):
    f = f"{tmp_path}/m*.vtk"
    s = f"{tmp_path}/m*.stl"
    cases = {
        "unknown keyword": (f"dump v all mesh/vtk 10 {f} stress colour", ["dump mesh/vtk (id v)", "'colour'", "neither a keyword"]),
        "unknown mesh id": (f"dump s all mesh/stl 10 {s} nope", ["dump mesh/stl (id s)", "'nope'", "fix mesh/surface"]),
        "not a mesh": (f"dump s all mesh/stl 10 {s} integr", ["dump mesh/stl (id s)", "'integr' is a fix nve/sphere, not a mesh"]),
        "liquid": (f"dump v all mesh/vtk 10 {f} liquid plate", ["dump mesh/vtk (id v)", "keyword 'liquid'", "not supported"]),
        "owner": (f"dump v all mesh/vtk 10 {f} owner", ["keyword 'owner'", "not supported"]),
        "temp": (f"dump v all mesh/vtk 10 {f} stress temp", ["keyword 'temp'", "not supported"]),
        "nothing selected": (f"dump v all mesh/vtk 10 {f} plate", ["dump mesh/vtk (id v)", "no dump quantity selected"]),
        "interpolate": (f"dump v all mesh/vtk 10 {f} output interpolate stress", ["'output interpolate'", "output face"]),
        "stl without star": (f"dump s all mesh/stl 10 {tmp_path}/m.stl", ["dump mesh/stl (id s)", "file", "'*'"]),
        "per-rank file": (f"dump v all mesh/vtk 10 {tmp_path}/m%.vtk stress", ["file", "'%'"]),
        "parallel xml": (f"dump v all mesh/vtk 10 {tmp_path}/m*.pvtp stress", ["file", "'.pvtp'", ".vtp (VTK XML)"]),
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


def test_dump_modify_first_and_every_act_other_keywords_are_errors(tmp_path):
    """'first', 'every' and 'every/time' act (LAMMPS's Output decides when a dump writes); every other
    dump_modify keyword is an ERROR naming dump_modify, the keyword and those three: the frames are written by
    the plugin, so the Dump base's formats, sorting, delay, padding ... would silently do nothing."""
    run(deck_head() + MESHES + ["run 1", f"dump s all mesh/stl 10 {tmp_path}/s*.stl pad", "dump_modify s first yes every 4",
                                f"dump v all mesh/vtk 10 {tmp_path}/v*.vtk area", "dump_modify v every/time 3e-6",
                                "run 9"]).close()
    # first: step 1 though off the interval; every/time 3e-6 at dt 1e-6: steps 3, 6, 9
    assert sorted(os.listdir(tmp_path)) == ["s1.stl", "s4.stl", "s8.stl", "v3.vtk", "v6.vtk", "v9.vtk"]
    s = f"{tmp_path}/e*.stl"
    # read by liblammps's Dump (refused at the run) or passed on to the style (refused at the line)
    for words in ["append yes", "sort id", "format line %g", "format float %g", "format none", "delay 5", "pad 3",
                  "maxfiles 2", "flush no", "header no", "pbc yes", "time yes", "units yes", "skip v_s", "colour red"]:
        msg = error_of(deck_head() + MESHES + ["variable s equal step", f"dump e all mesh/stl 10 {s} pad",
                                               f"dump_modify e {words}", "run 0"])
        assert msg is not None, words
        for needle in ["dump mesh/stl (id e)", f"dump_modify keyword '{words.split()[0]}'", "'first', 'every' and 'every/time'"]:
            assert needle in msg, f"{words}: '{needle}' not in: {msg}"


def test_mesh_dumps_survive_plugin_unload_and_clear(tmp_path):
    """LAMMPS 22 Jul 2025's 'plugin unload' does not take dump styles, so the mesh dumps stay in LAMMPS's table
    after 'plugin clear' has unloaded every other style of the plugin (and the loader has dlclose'd it): the
    plugin is linked -z nodelete, so the dump still runs (a segfault before). In a child process."""
    script = tmp_path / "unload.py"
    script.write_text(
        "from dembridge import new_lammps\nlmp = new_lammps(screen=True)\n"
        f"for c in ['plugin unload dump mesh/stl', 'plugin clear', 'units si', 'atom_style sphere',\n"
        f"          'region box block -1 1 -1 1 -1 1', 'create_box 1 box', 'dump d all mesh/stl 10 {tmp_path}/u*.stl',\n"
        f"          'run 0']:\n    lmp.command(c)\nlmp.close()\n")
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"))
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "Ignoring unload: dump is not a supported plugin style" in r.stdout
    assert "Unloading fix style mesh/surface" in r.stdout
    assert (tmp_path / "u0.stl").read_text().strip() == ""  # no mesh left: an empty frame, written
