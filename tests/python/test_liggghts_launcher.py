"""dembridge-liggghts on LIGGGHTS decks (tests/data/liggghts_decks, provenance in tests/data/README.md):
each deck also runs live in LIGGGHTS 3.8; through the launcher, serial and on 2 ranks, it must end
without an ERROR and print no WARNING that LIGGGHTS does not print.

The decks that need a command the plugin does not have yet are expected to fail with that command
named (xfail strict): when it lands the deck passes, the xfail turns into a failure, and its entry
in PENDING is to be removed."""
import struct

import pytest

from liggghts_decks import errors, run_launcher, run_liggghts, warnings
from vtk_reader import read_legacy

# deck -> the error texts of the commands it needs that are not in the plugin yet
PENDING = {
    "in.packing_like": ["Unrecognized fix style 'particletemplate/sphere'",
                        "Unrecognized fix style 'particledistribution/discrete'",
                        "Unrecognized fix style 'insert/pack'"],
    "in.chute_wear_like": ["only 'wear off' is supported", "Unrecognized fix style 'particletemplate/sphere'",
                           "Unrecognized fix style 'particledistribution/discrete'",
                           "Unrecognized fix style 'insert/stream'", "keyword 'wear': not supported"],
    "in.conveyor_like": ["Unrecognized fix style 'particletemplate/sphere'",
                         "Unrecognized fix style 'particledistribution/discrete'",
                         "Unrecognized fix style 'insert/stream'",
                         "Unrecognized fix style 'check/timestep/gran'"],
    "in.moving_mesh_like": ["Unrecognized fix style 'particletemplate/sphere'",
                            "Unrecognized fix style 'particledistribution/discrete'",
                            "Unrecognized fix style 'insert/pack'"],
    "in.mesh_gran_like": ["Unrecognized fix style 'particletemplate/sphere'",
                          "Unrecognized fix style 'particledistribution/discrete'",
                          "Unrecognized fix style 'insert/stream'",
                          "Unrecognized fix style 'check/timestep/gran'"],
    "in.insert_stream_like": ["Unrecognized fix style 'particletemplate/sphere'",
                              "Unrecognized fix style 'particledistribution/discrete'",
                              "Unrecognized fix style 'insert/stream'"],
    "in.heat_like": ["Unrecognized fix style 'heat/gran'", "Unrecognized fix style 'particletemplate/sphere'",
                     "Unrecognized fix style 'particledistribution/discrete'",
                     "Unrecognized fix style 'insert/pack'"],
    "in.cohesion_like": ["Unrecognized fix style 'particletemplate/sphere'",
                         "Unrecognized fix style 'particledistribution/discrete'",
                         "Unrecognized fix style 'insert/pack'"],
}
DECKS = list(PENDING) + ["in.launcher_rewrites"]


class MissingCommand(Exception):
    """The launcher run stopped at a command the plugin does not have yet (named in the message)."""


def check_like_liggghts(deck, out, lig_out, label):
    missing = [p for p in PENDING.get(deck, []) if any(p in e for e in errors(out))]
    if missing:
        raise MissingCommand(f"{deck} ({label}) needs a command not yet in the plugin: {missing[0]}")
    assert not errors(out), f"{deck} ({label}):\n" + "\n".join(errors(out)) + "\n" + out[-3000:]
    extra = warnings(out) - warnings(lig_out)
    assert not extra, f"{deck} ({label}) prints warnings LIGGGHTS does not: {sorted(extra)}"


@pytest.mark.parametrize("deck", [
    pytest.param(d, marks=pytest.mark.xfail(strict=True, raises=MissingCommand,
                                            reason="; ".join(PENDING[d]))) if d in PENDING else d
    for d in DECKS])
def test_deck_runs_through_the_launcher_as_in_liggghts(deck, tmp_path):
    rc, lig = run_liggghts(deck, tmp_path / "liggghts")
    assert rc == 0 and not errors(lig), f"LIGGGHTS itself fails on {deck}:\n{lig[-3000:]}"
    for nprocs in (1, 2):
        rc, out = run_launcher(deck, tmp_path / f"launcher{nprocs}", nprocs=nprocs)
        check_like_liggghts(deck, out, lig, f"{nprocs} rank(s)")
        assert rc == 0, out[-3000:]


def read_text_dump(path):
    """{id: row of floats} of a LAMMPS/LIGGGHTS text dump, and its column names."""
    lines = path.read_text().splitlines()
    k = next(i for i, ln in enumerate(lines) if ln.startswith("ITEM: ATOMS"))
    cols = lines[k].split()[2:]
    rows = {}
    for ln in lines[k + 1:]:
        if ln.strip():
            v = ln.split()
            rows[int(v[0])] = v
    return cols, rows


@pytest.fixture(scope="module")
def rewrites_runs(tmp_path_factory):
    """in.launcher_rewrites in LIGGGHTS and through the launcher (serial, 2 ranks): their folders."""
    base = tmp_path_factory.mktemp("rewrites")
    deck = "in.launcher_rewrites"
    rc, lig = run_liggghts(deck, base / "liggghts")
    assert rc == 0, lig[-2000:]
    out = {}
    for n in (1, 2):
        rc, text = run_launcher(deck, base / f"launcher{n}", nprocs=n)
        assert rc == 0, text[-3000:]
        out[n] = text
    return base, out


STEPS = (0, 200, 400, 600)


def test_rewritten_deck_follows_liggghts_bit_for_bit_on_1_and_2_ranks(rewrites_runs):
    base, _ = rewrites_runs
    for n in (1, 2):
        for step in STEPS:
            name = f"post/particles_{step}.txt"
            cols, lig = read_text_dump(base / "liggghts" / name)
            cols2, ours = read_text_dump(base / f"launcher{n}" / name)
            assert cols == cols2 and lig.keys() == ours.keys() and len(lig) == 140
            for i in lig:  # %.17g text: equal strings are equal doubles
                assert [float(x) for x in lig[i]] == [float(x) for x in ours[i]], (n, step, i)


def test_each_rewrite_is_printed_once_in_the_log(rewrites_runs):
    base, out = rewrites_runs
    log = (base / "launcher1" / "log.lammps").read_text()
    for rule in ("atom_style granular -> atom_style sphere", "dynamic -> dynamic/dof",
                 "format STRING -> format line STRING", "units box added", "included files are translated"):
        printed = [ln for ln in log.splitlines() if ln.startswith("dembridge-liggghts:") and rule in ln]
        assert len(printed) == 1, (rule, printed)
    assert "inc.output_liggghts line 4" in log  # the rewrite inside the included file names it


def test_custom_vtk_equals_the_17_digit_text_dump_of_the_same_run(rewrites_runs):
    base, _ = rewrites_runs
    for n in (1, 2):
        for step in STEPS:
            cols, txt = read_text_dump(base / f"launcher{n}" / f"post/particles_{step}.txt")
            col = {c: k for k, c in enumerate(cols)}
            vtk = read_legacy(base / f"launcher{n}" / f"post/particles_{step}.vtk")
            ids = [r[0] for r in vtk["arrays"]["id"][2]]
            assert ids == sorted(txt)  # rows sorted by ID whatever the rank count
            for p, i in zip(vtk["points"], ids):  # points are floats: read back, the same float as x
                assert [as_float32(v) for v in p] == [as_float32(float(txt[i][col[c]])) for c in "xyz"]
            vectors = {"i": ("ix", "iy", "iz"), "v": ("vx", "vy", "vz"), "f": ("fx", "fy", "fz"),
                       "omega": ("omegax", "omegay", "omegaz")}
            for name, (comps, typ, rows) in vtk["arrays"].items():
                fields = vectors.get(name, (name,))
                assert comps == len(fields)
                assert typ == ("int" if name in ("id", "type", "i") else "double"), name
                for row, i in zip(rows, ids):
                    assert row == [float(txt[i][col[c]]) if typ == "double" else int(txt[i][col[c]])
                                   for c in fields], (name, i)


def as_float32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def test_custom_vtk_has_the_layout_of_liggghts_own_files(rewrites_runs):
    base, _ = rewrites_runs
    lig_files = sorted(p.name for p in (base / "liggghts" / "post").glob("*.vtk"))
    our_files = sorted(p.name for p in (base / "launcher1" / "post").glob("*.vtk"))
    assert lig_files == our_files  # frames, bounding boxes and the mesh dump: the same names
    assert (base / "launcher1" / "post" / "particles.vtk.series").is_file()
    for step in STEPS:
        lig = read_legacy(base / "liggghts" / f"post/particles_{step}.vtk")
        ours = read_legacy(base / "launcher1" / f"post/particles_{step}.vtk")
        for key in ("version", "title", "dataset", "npoint_data"):
            assert lig[key] == ours[key], key
        assert lig["order"] == ours["order"]  # id type mass i v f radius omega: LIGGGHTS's order
        assert [lig["arrays"][a][:2] for a in lig["order"]] == [ours["arrays"][a][:2] for a in ours["order"]]
        by_id = {r[0]: k for k, r in enumerate(lig["arrays"]["id"][2])}
        for k, (i,) in enumerate(ours["arrays"]["id"][2]):
            j = by_id[i]
            # LIGGGHTS prints points with 6 digits and doubles with 11: equal to that many digits
            assert ours["points"][k] == pytest.approx(lig["points"][j], rel=1e-5, abs=1e-9)
            for a in ours["order"]:
                assert ours["arrays"][a][2][k] == pytest.approx(lig["arrays"][a][2][j], rel=1e-10, abs=1e-20), a
        box_l = read_legacy(base / "liggghts" / f"post/particles_boundingBox_{step}.vtk")
        box_o = read_legacy(base / "launcher1" / f"post/particles_boundingBox_{step}.vtk")
        assert box_l["dataset"] == box_o["dataset"] == "RECTILINEAR_GRID"
        assert box_l["coordinates"] == box_o["coordinates"] == {"X": [-0.05, 0.05], "Y": [-0.03, 0.03],
                                                                "Z": [-0.04, 0.08]}
        # dump mesh/gran/VTK: LIGGGHTS's name of dump mesh/vtk (its layout is tested with that name)
        mesh_l = (base / "liggghts" / f"post/mesh_{step}.vtk").read_text().splitlines()
        mesh_o = (base / "launcher1" / f"post/mesh_{step}.vtk").read_text().splitlines()
        assert mesh_l[3] == mesh_o[3] == "DATASET POLYDATA"
