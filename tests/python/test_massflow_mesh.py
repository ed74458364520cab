"""fix massflow/mesh against LIGGGHTS 3.8 run live (tests/data/liggghts-massflow: 146 of 200 particles
falling through a face in 14000 steps): the thermo columns (mass, count, rates; point_at_outlet; an
upward count multiple) as printed (%.17g) and the file of crossing particles; on 2 ranks the counts and
the file's lines, the masses to 1e-12. Bad input: ERRORs naming the fix and the argument."""
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "oracle"))
import oracle_harness as oh  # noqa: E402

from bad_input_check import assert_error  # noqa: E402
from test_bad_input import run_deck  # noqa: E402
from dembridge import thermo_rows  # noqa: E402
from dembridge.outputs import read_dump_rows  # noqa: E402

pytestmark = pytest.mark.two_cores  # 2 ranks against a LIGGGHTS run that both cases share

CASE = ROOT / "tests" / "data" / "liggghts-massflow"
FUNNEL = ROOT / "tests" / "data" / "liggghts-walls" / "hopper200_funnel_settle"  # data.txt, funnel.stl
FACE = CASE / "face.stl"


def deck(steps=14000):
    text = (CASE / "in.liggghts").read_text().replace("FACE", str(FACE))
    return text.replace("run             14000", f"run             {steps}")


def rows(log):
    return [r for r in thermo_rows(log) if len(r) == 10]


def crossing_lines(folder, nprocs):
    names = ["massflow.txt"] if nprocs == 1 else [f"massflow.txt.{r}" for r in range(nprocs)]
    lines = []
    for n in names:
        text = (Path(folder) / n).read_text().splitlines()
        assert text[0] == "# ID diameter x y z u v w  (ex ey ez, color)"
        lines += text[1:]
    return sorted(lines)


@pytest.fixture(scope="module")
def liggghts(tmp_path_factory):
    wd = tmp_path_factory.mktemp("liggghts")
    oh.run_liggghts(FUNNEL, wd, deck_text=deck())
    return wd


@pytest.mark.parametrize("nprocs", [1, 2])
def test_massflow_against_liggghts(liggghts, tmp_path, nprocs):
    steps = 14000 if nprocs == 1 else 6000  # 2 ranks: the first 6000 steps (17 crossings), for the test-time budget
    oh.run_lammps(oh.liggghts_to_lammps_deck(deck(steps), syntax="3x"), tmp_path, nprocs=nprocs,
                  files=[FUNNEL / "data.txt", FUNNEL / "funnel.stl"])
    ref, got = rows(liggghts / "log.liggghts"), rows(tmp_path / "log.lammps")
    assert len(ref) == 15 and len(got) == steps // 1000 + 1
    assert ref[-1][3] == 146 and ref[-1][7] == 146  # the deck does count
    for a, b in zip(ref, got):
        assert a[:2] == b[:2]
        assert (a[3], a[7], a[9]) == (b[3], b[7], b[9])  # counts
        if nprocs == 1:
            assert a == b  # every column as printed (%.17g)
        else:
            for col in (2, 4, 5, 6, 8):
                x, y = a[col], b[col]
                assert abs(x - y) <= 1e-12 * abs(x), (a[0], col, x, y)
    ours, theirs = crossing_lines(tmp_path, nprocs), crossing_lines(liggghts, 1)
    assert len(ours) == int(got[-1][3]) > 0
    if nprocs == 1:
        assert ours == theirs
    else:  # LIGGGHTS ran to 14000: its file holds these 17 crossings and later ones
        assert set(ours) <= set(theirs)


def delete_deck(steps=14000):
    text = (CASE / "in.delete_atoms").read_text().replace("FACE", str(FACE))
    return text.replace("run             14000", f"run             {steps}")


@pytest.fixture(scope="module")
def liggghts_delete(tmp_path_factory):
    wd = tmp_path_factory.mktemp("liggghts_delete")
    oh.run_liggghts(FUNNEL, wd, deck_text=delete_deck())
    return wd


def dump_atoms(path):
    """{step: the frame's atom rows (id, x, y, z, vx, vy, vz) sorted by id} of the %.17g text dump."""
    return {step: sorted(tuple(r) for r in rows) for step, rows in read_dump_rows(path).items()}


@pytest.mark.parametrize("nprocs", [1, 2])
def test_delete_atoms_deletes_the_particles_liggghts_deletes(liggghts_delete, tmp_path, nprocs):
    """delete_atoms yes: 147 of the 200 particles counted and deleted as they pass the face. One rank: every
    thermo column (with f_mf[5], f_mf[6]: the mass and number deleted) and every remaining particle
    (%.17g) as LIGGGHTS's; the same crossing-file lines. Two ranks (the first 6000 steps): the same counts
    and particles deleted, the masses and states to round-off."""
    steps = 14000 if nprocs == 1 else 6000
    oh.run_lammps(oh.liggghts_to_lammps_deck(delete_deck(steps), syntax="3x"), tmp_path, nprocs=nprocs,
                  files=[FUNNEL / "data.txt", FUNNEL / "funnel.stl"])
    ref, got = rows(liggghts_delete / "log.liggghts"), rows(tmp_path / "log.lammps")
    assert len(ref) == 15 and len(got) == steps // 1000 + 1
    assert ref[-1][1] == 53 and ref[-1][3] == 147 and ref[-1][7] == 147  # the deck does delete
    for a, b in zip(ref, got):
        assert a[:2] == b[:2]  # step, atoms left
        assert (a[3], a[7], a[8]) == (b[3], b[7], b[8])  # counted, deleted, point_at_outlet count
        assert a[7] <= a[3] and a[1] + a[7] == 200  # deleted at the next re-neighbouring after the count
        if nprocs == 1:
            assert a == b  # every column as printed (%.17g)
        else:
            for col in (2, 4, 5, 6):
                x, y = a[col], b[col]
                assert abs(x - y) <= 1e-12 * abs(x), (a[0], col, x, y)
    ref_d, got_d = dump_atoms(liggghts_delete / "dump.txt"), dump_atoms(tmp_path / "dump.txt")
    for step, atoms in got_d.items():
        assert [r[0] for r in atoms] == [r[0] for r in ref_d[step]]  # the same particles left
        if nprocs == 1:
            assert atoms == ref_d[step]
        else:
            assert max(abs(x - y) for p, q in zip(atoms, ref_d[step]) for x, y in zip(p[1:], q[1:])) <= 1e-9
    ours, theirs = crossing_lines(tmp_path, nprocs), crossing_lines(liggghts_delete, 1)
    assert len(ours) == int(got[-1][3])
    assert ours == theirs if nprocs == 1 else set(ours) <= set(theirs)


BASE = ["units si", "atom_style sphere", "boundary f f f", "newton off", "comm_modify vel yes",
        "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05", "create_box 1 box",
        "create_atoms 1 single 0.0 0.0 0.04 units box", "set group all diameter 0.008 density 2500",
        "fix m1 all property/global youngsModulus peratomtype 5.e7", "fix m2 all property/global poissonsRatio peratomtype 0.3",
        "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
        "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
        "pair_style gran model hertz tangential history", "pair_coeff * *", "timestep 1e-6",
        f"fix face all mesh/surface file {FACE} type 1", f"fix cone all mesh/surface file {FUNNEL / 'funnel.stl'} type 1"]
M = "fix mf all massflow/mesh"
BAD = {
    "no_mesh": (BASE + [M + " vec_side 0 0 -1"], ["fix massflow/mesh (id mf)", "mesh", "missing"]),
    "unknown_mesh": (BASE + [M + " mesh nope vec_side 0 0 -1"], ["(id mf)", "'nope'", "fix mesh/surface"]),
    "no_side": (BASE + [M + " mesh face"], ["(id mf)", "vec_side", "point_at_outlet"]),
    "zero_side": (BASE + [M + " mesh face vec_side 0 0 0"], ["(id mf)", "vec_side", "non-zero"]),
    "side_in_plane": (BASE + [M + " mesh face vec_side 1 0 0"], ["(id mf)", "vec_side", "mesh plane"]),
    "count_word": (BASE + [M + " mesh face vec_side 0 0 -1 count twice"], ["(id mf)", "count", "'twice'"]),
    "outlet_multiple": (BASE + [M + " mesh face point_at_outlet 0 0 -1"], ["(id mf)", "point_at_outlet", "count once"]),
    "inside_out_first": (BASE + [M + " mesh face inside_out point_at_outlet 0 0 -1 count once"], ["(id mf)", "inside_out"]),
    "delete_atoms_word": (BASE + [M + " mesh face vec_side 0 0 -1 count once delete_atoms maybe"], ["(id mf)", "delete_atoms", "'maybe'"]),
    "delete_atoms_no_map": (BASE + [M + " mesh face vec_side 0 0 -1 count once delete_atoms yes", "run 0"],
                            ["(id mf)", "delete_atoms yes", "atom_modify map array"]),
    "unknown_keyword": (BASE + [M + " mesh face vec_side 0 0 -1 colour red"], ["(id mf)", "'colour'", "unknown keyword"]),
    "not_planar": (BASE + [M + " mesh cone vec_side 0 0 -1", "run 0"], ["(id mf)", "planar", "point_at_outlet"]),
    "sum_property_missing": (BASE + [M + " mesh face vec_side 0 0 -1 sum_property Temp", "run 0"],
                             ["(id mf)", "sum_property", "'Temp'"]),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_massflow_bad_input(name):
    assert_error(name, *BAD[name])


def test_massflow_good_deck_runs():
    assert run_deck(BASE + [M + " mesh face vec_side 0 0 -1", "run 2"]) is None
