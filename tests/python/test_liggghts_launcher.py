"""dembridge-liggghts on LIGGGHTS decks (tests/data/liggghts_decks, provenance in tests/data/README.md):
each deck also runs live in LIGGGHTS 3.8; through the launcher, serial and on 2 ranks, it must end
without an ERROR and print no WARNING that LIGGGHTS does not print.

The decks that need a command the plugin does not have yet are expected to fail with that command
named (xfail strict): when it lands the deck passes, the xfail turns into a failure, and its entry
in PENDING is to be removed."""
import math
import os
import struct

import pytest

from dembridge import lmp_executable, mpiexec
from dembridge.liggghts_deck import rewrite_words, split_words, translate_text
from dembridge.run import _plugin_env
from test_bad_input import run_deck
from liggghts_decks import LAUNCHER, copy_deck, errors, launcher_env, run, run_launcher, run_liggghts, warnings
from vtk_reader import read_legacy

pytestmark = pytest.mark.two_cores  # the shared launcher runs include 2 ranks

# deck -> the error texts of the commands it needs that are not in the plugin yet
PENDING = {}
# deck -> why it still differs from LIGGGHTS although every command exists (xfail strict on the assertion)
DIFFERS = {}
# these run now (three of the insert/stream decks since fix insert/stream):
PASSING = ["in.packing_like", "in.mesh_gran_like", "in.moving_mesh_like", "in.heat_like", "in.cohesion_like",
           "in.chute_wear_like", "in.conveyor_like", "in.insert_stream_like"]
DECKS = list(PENDING) + list(DIFFERS) + PASSING  # in.launcher_rewrites: the same checks on the runs of the rewrites_runs fixture


class MissingCommand(Exception):
    """The launcher run stopped at a command the plugin does not have yet (named in the message)."""


def check_like_liggghts(deck, out, lig_out, label):
    assert not errors(out), f"{deck} ({label}):\n" + "\n".join(errors(out)) + "\n" + out[-3000:]
    extra = warnings(out) - warnings(lig_out)
    assert not extra, f"{deck} ({label}) prints warnings LIGGGHTS does not: {sorted(extra)}"


@pytest.mark.parametrize("deck", [
    pytest.param(d, marks=pytest.mark.xfail(strict=True, raises=MissingCommand,
                                            reason="; ".join(PENDING[d]))) if d in PENDING else
    pytest.param(d, marks=pytest.mark.xfail(strict=True, raises=AssertionError, reason=DIFFERS[d])) if d in DIFFERS
    else d
    for d in DECKS])
def test_deck_runs_through_the_launcher_as_in_liggghts(deck, tmp_path):
    """Also: the packing deck's growth (fix adapt with an atom-style diameter) follows LIGGGHTS bit for bit on
    one rank, and to round-off on two."""
    # serial first: a deck stopping at a command not yet in the plugin costs no LIGGGHTS run
    rc1, out1 = run_launcher(deck, tmp_path / "launcher1")
    missing = [p for p in PENDING.get(deck, []) if any(p in e for e in errors(out1))]
    if missing:
        raise MissingCommand(f"{deck} needs a command not yet in the plugin: {missing[0]}")
    rc, lig = run_liggghts(deck, tmp_path / "liggghts")
    assert rc == 0 and not errors(lig), f"LIGGGHTS itself fails on {deck}:\n{lig[-3000:]}"
    check_like_liggghts(deck, out1, lig, "1 rank")
    assert rc1 == 0, out1[-3000:]
    rc, out = run_launcher(deck, tmp_path / "launcher2", nprocs=2)
    check_like_liggghts(deck, out, lig, "2 ranks")
    assert rc == 0, out[-3000:]
    for name in sorted(p.name for p in (tmp_path / "liggghts" / "post").glob("*.txt")):
        cols, ref = read_text_dump(tmp_path / "liggghts" / "post" / name)
        for n, tol in ((1, 0.0), (2, 1e-12)):
            _, ours = read_text_dump(tmp_path / f"launcher{n}" / "post" / name)
            assert ref.keys() == ours.keys(), (name, n)
            worst = max((abs(float(a) - float(b)) for i in ref for a, b in zip(ref[i], ours[i])), default=0.0)  # step 0 of an insertion deck: no atoms
            assert worst <= tol, (name, n, worst)


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
    assert rc == 0 and not errors(lig), lig[-2000:]
    out = {"liggghts": lig}
    for n in (1, 2):
        rc, text = run_launcher(deck, base / f"launcher{n}", nprocs=n)
        assert rc == 0, text[-3000:]
        out[n] = text
    return base, out


def test_rewritten_deck_runs_without_error_or_warning_liggghts_does_not_print(rewrites_runs):
    _, out = rewrites_runs
    for n in (1, 2):
        check_like_liggghts("in.launcher_rewrites", out[n], out["liggghts"], f"{n} rank(s)")


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


def test_standard_input_and_mpiexec_read_the_deck_as_liggghts_does(rewrites_runs, tmp_path):
    """`dembridge-liggghts < deck` (serial and under mpiexec -n 2, where only rank 0 has the deck on its
    standard input) writes the same frames as `-in deck`."""
    base, _ = rewrites_runs
    for n in (1, 2):
        where = copy_deck("in.launcher_rewrites", tmp_path / f"stdin{n}")
        cmd = LAUNCHER if n == 1 else [mpiexec(), "-n", "2"] + LAUNCHER
        rc, out = run(cmd, where, stdin=where / "in.launcher_rewrites", env=launcher_env())
        assert rc == 0 and not errors(out), out[-2000:]
        assert "standard input line 4: atom_style granular" in out
        for step in STEPS:
            name = f"post/particles_{step}.txt"
            assert read_text_dump(where / name) == read_text_dump(base / "launcher1" / name)


def test_translate_writes_a_lammps_deck_that_plain_lmp_runs_the_same(rewrites_runs, tmp_path):
    base, _ = rewrites_runs
    where = copy_deck("in.launcher_rewrites", tmp_path / "translate")
    rc, out = run(LAUNCHER + ["-in", "in.launcher_rewrites", "--translate", "in.lammps"], where, env=launcher_env())
    assert rc == 0, out
    assert not list((where / "post").iterdir())  # --translate does not run
    deck = (where / "in.lammps").read_text()
    assert "atom_style\tgranular" not in deck and "atom_style sphere 1" in deck
    assert "include in.lammps.inc.output_liggghts" in deck  # the included file, translated beside it
    assert 'format line "%d %d' in (where / "in.lammps.inc.output_liggghts").read_text()
    rc, out = run([lmp_executable(), "-in", "in.lammps"], where, env=_plugin_env(os.environ))
    assert rc == 0 and not errors(out), out[-2000:]
    for step in STEPS:
        name = f"post/particles_{step}.txt"
        assert read_text_dump(where / name) == read_text_dump(base / "launcher1" / name)
    # a file that dembridge-liggghts did not write is never overwritten
    (where / "mine.in").write_text("# my own deck\n")
    rc, out = run(LAUNCHER + ["-in", "in.launcher_rewrites", "--translate", "mine.in"], where, env=launcher_env())
    assert rc != 0 and "exists and was not written by dembridge-liggghts" in out
    assert (where / "mine.in").read_text() == "# my own deck\n"


@pytest.mark.parametrize("words, expected", [
    ("atom_style granular", "atom_style sphere 1"),
    ("atom_style hybrid granular ellipsoid", "atom_style hybrid sphere 1 ellipsoid"),
    ("atom_style sphere", None),
    ('dump_modify d format "%d %g" sort id', 'dump_modify d format line "%d %g" sort id'),
    ('dump_modify d format line "%d %g"', None),
    ("dump_modify d format float %20.15g", None),
    ('dump_modify d format 2 "%g"', None),
    ("compute_modify thermo_temp dynamic yes extra 2", "compute_modify thermo_temp dynamic/dof yes extra/dof 2"),
    ("set region half property/atom Temp 800.", "set region half d_Temp 800."),
    ("set atom 3 property/atom vel 1 2 3 type 2",
     "set atom 3 d2_vel[1] 1 d2_vel[2] 2 d2_vel[3] 3 type 2"),
    ("region r block 0 1 0 1 0 1", "region r block 0 1 0 1 0 1 units box"),
    ("region r block 0 1 0 1 0 1 units lattice", None),
    ("region r delete", None),
    ("velocity all set 0 0 -1", "velocity all set 0 0 -1 units box"),
    ("create_atoms 1 single 0 0 0", "create_atoms 1 single 0 0 0 units box"),
    ("thermo_style custom step atoms ke c_1 vol", "thermo_style custom step atoms c_thermo_kin_eng c_1 vol"),
    ("thermo_style custom step atoms c_ke", None),
    ("thermo_style one", None),
    ("fix f all nve/sphere", None),
])
def test_rewrite_of_one_command(words, expected):
    got, rules = rewrite_words(split_words(words)[0])
    assert (" ".join(got) if rules else None) == expected


def test_continued_lines_comments_and_variable_file_names(tmp_path):
    text = 'dump_modify d &\n  format "%d %g" # ids\nlabel loop\ninclude ${name}\n'
    t = translate_text(text, "deck", notes=False, resolve=lambda p, c: p)
    lines = t.text.split("\n")
    assert lines[1] == 'dump_modify d format line "%d %g" # ids' and lines[2] == ""  # the line count kept
    assert "label loop" in lines and "include ${name}" in lines
    assert {r.rule for r in t.rewrites} == {"format", "variable_file"}


def test_set_diameter_keeps_the_density_as_liggghts(tmp_path):
    """LIGGGHTS's `set ... diameter` keeps the density (LAMMPS's keeps the mass): after the rewrite the
    mass is rho*4/3*pi*r^3 (closed form) for the new radius."""
    deck = "\n".join(["atom_style granular", "atom_modify map array", "units si", "region r block -1 1 -1 1 -1 1",
                      "create_box 1 r", "create_atoms 1 single 0 0 0", "create_atoms 1 single 0.5 0 0",
                      "set atom 1 diameter 0.1 density 2500", "set atom 2 diameter 0.2 density 1000",
                      "set group all diameter 0.3", "variable m1 equal mass[1]", "variable m2 equal mass[2]",
                      'print "MASSES ${m1} ${m2}"']) + "\n"
    (tmp_path / "in.d").write_text(deck)
    rc, out = run(LAUNCHER + ["-in", "in.d", "-log", "none"], tmp_path, env=launcher_env())
    assert rc == 0, out[-2000:]
    m1, m2 = (float(x) for x in next(ln for ln in out.splitlines() if ln.startswith("MASSES")).split()[1:])
    vol = 4.0 / 3.0 * math.pi * 0.15 ** 3
    assert m1 == pytest.approx(2500 * vol, rel=1e-14) and m2 == pytest.approx(1000 * vol, rel=1e-14)


BAD = [
    ("dump d all custom/vtk 10 post/a_*.vtk id speed", "dump custom/vtk (id d): attribute 'speed': unknown"),
    ("dump d all custom/vtk 10 post/a_*.vtk", "dump custom/vtk (id d): attributes: none given"),
    ("dump d all custom/vtk 10 post/a_*.vtk id c_nope", "attribute 'c_nope': no compute with ID 'nope'"),
    ("dump d all custom/vtk 10 post/a_*.vtk id f_nope[2]", "attribute 'f_nope[2]': no fix with ID 'nope'"),
    ("dump d all custom/vtk 10 post/a_*.vtk id v_nope", "attribute 'v_nope': no variable named 'nope'"),
    ("dump d all custom/vtk 10 post/a_%.vtk id", "file 'post/a_%.vtk': '%' (a file per rank) is not allowed"),
    ("dump d all custom/vtk 10 post/a_*.vti id", "file 'post/a_*.vti': '.vti' is not written; expected .vtk"),
    ("dump d all custom/vtk 10 post/a_*.vtk id c_ke", "compute 'ke' has no per-atom values"),
    ("dump d all custom/vtk 10 post/a_*.vtk id\ndump_modify d thresh x > 0",
     "dump_modify keyword 'thresh': not supported"),
    ("dump d all custom/vtk 10 post/a_*.vtk id\ndump_modify d pad 5\nrun 0",
     "dump_modify keyword 'pad': not supported"),
    ("dump d all custom/vtm 10 post/a_*.vtm id", "dump style 'custom/vtm' is not available: use dump custom/vtk"),
    ("dump d all local/gran/vtk 10 post/a_*.vtk", "use compute pair/gran/local"),
    ("communicate double vel yes", "communicate: style 'double': expected 'single' or 'multi'"),
    ("communicate", "communicate: expected a style"),
    ("thermo_log post/thermo.txt", "thermo_log: LIGGGHTS's command 'thermo_log' is not available: write"),
    ("modify_timing on", "modify_timing: LIGGGHTS's command 'modify_timing' is not available"),
    ("variable d atom 0.01\nfix a all adapt 10 atom diameter v_d reset maybe",
     "fix adapt (id a): keyword 'reset maybe': expected reset yes|no"),
    # an equal-style variable is LAMMPS's own fix adapt: the built-in's error for a static atom_style sphere
    ("variable e equal 0.02\nfix a all adapt 1 atom diameter v_e\nrun 0",
     "Fix adapt changes atom radii but atom_style sphere is not dynamic"),
]


@pytest.mark.parametrize("line, message", BAD)
def test_bad_input_is_an_error_naming_the_command_and_argument(line, message):
    deck = ["atom_style sphere", "units si", "region r block -1 1 -1 1 -1 1", "create_box 1 r",
            "create_atoms 1 single 0 0 0 units box", "compute ke all ke", "communicate single vel yes"] + \
        line.split("\n")
    err = run_deck(deck)  # in-process: one LAMMPS instance per case, the plugin loaded once
    assert err is not None and message in err, err


def test_communicate_sets_comm_modify_in_a_plain_lmp_run(tmp_path):
    """`communicate single vel yes` is a command of the plugin: plain lmp accepts it and ghost atoms then
    carry velocities (LAMMPS's info comm says so)."""
    deck = "\n".join(["units si", "atom_style sphere", "region r block -1 1 -1 1 -1 1", "create_box 1 r",
                      "communicate single vel yes cutoff 0.5", "info communication"]) + "\n"
    (tmp_path / "in.c").write_text(deck)
    rc, out = run([lmp_executable(), "-in", "in.c", "-log", "none"], tmp_path, env=_plugin_env(os.environ))
    assert rc == 0, out[-1500:]
    assert "Communication mode = single" in out and "Communicate velocities for ghost atoms = yes" in out
    assert "Communication cutoff = 0.5" in out
