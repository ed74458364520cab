"""A shrink-wrapped box is wrapped around the meshes as in LIGGGHTS 3.8 (run live, /usr/bin/liggghts), through
dembridge-liggghts on two decks of tests/data/liggghts_decks:

* in.box_wrap_s: boundary s s s, an empty created box inside an STL box; the box becomes the mesh's box, so the
  40 particles of insert/pack land (without the wrap the run stops: the mesh lies outside the box).
* in.box_follows_mesh: boundary s m m, a piston mesh moved by fix move/mesh up and sideways out of the initial
  box, lifting 12 particles: the faces follow the mesh at every re-neighbouring, and after the mesh stops.

Every thermo row (step, atoms, xlo..zhi, printed %.17g) and every dump line (%.17g) is LIGGGHTS's, on one rank
and on two (the static mesh is split over the ranks there, the moving one whole)."""
import pytest

from dembridge import thermo_rows
from liggghts_decks import errors, run_launcher, run_liggghts

DECKS = ["in.box_wrap_s", "in.box_follows_mesh"]


def box_rows(folder):
    """(step, atoms, xlo, xhi, ylo, yhi, zlo, zhi) of every thermo row of the log."""
    return [r for r in thermo_rows(folder / "log.liggghts" if (folder / "log.liggghts").exists() else
                                   folder / "log.lammps") if len(r) == 8]


def dump_frames(path):
    """{step: sorted atom lines as numbers} of a text dump."""
    frames, step, lines = {}, None, path.read_text().splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1])
            frames[step] = []
            i += 2
        elif lines[i].startswith("ITEM: ATOMS"):
            i += 1
            while i < len(lines) and not lines[i].startswith("ITEM"):
                frames[step].append(tuple(float(x) for x in lines[i].split()))
                i += 1
            frames[step].sort()
        else:
            i += 1
    return frames


@pytest.fixture(scope="module")
def liggghts(tmp_path_factory):
    out = {}
    for deck in DECKS:
        where = tmp_path_factory.mktemp(deck.replace(".", "_"))
        rc, text = run_liggghts(deck, where)
        assert rc == 0 and not errors(text), text[-2000:]
        out[deck] = where
    return out


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
@pytest.mark.parametrize("deck", DECKS)
def test_box_bounds_and_particles_as_liggghts(liggghts, deck, nprocs, tmp_path):
    rc, text = run_launcher(deck, tmp_path, nprocs=nprocs)
    assert rc == 0 and not errors(text), text[-3000:]
    ref, got = box_rows(liggghts[deck]), box_rows(tmp_path)
    steps = {"in.box_wrap_s": 9, "in.box_follows_mesh": 4 + 8 + 3}[deck]  # rows of all runs, setup rows included
    assert len(ref) == len(got) == steps
    if deck == "in.box_wrap_s":
        assert ref[-1][1] == 40  # every particle inserted, none lost
        assert ref[-1][2:] == (-0.060002, 0.060002, -0.030001999999999997, 0.030001999999999997,
                               -2.0000000000000003e-06, 0.080002000000000004)  # the STL box -+ 1e-4 of the created one
    else:
        assert ref[-1][3] > 0.04 and ref[6][3] > 0.012  # xhi left the initial box (0.02) with the piston
    if nprocs == 1 or deck == "in.box_wrap_s":  # here the mesh alone sets the bounds
        assert got == ref
    else:  # two ranks: the particles that set the bounds follow LIGGGHTS to round-off
        for a, b in zip(ref, got):
            assert a[:2] == b[:2]
            for x, y in zip(a[2:], b[2:]):
                assert abs(x - y) <= 1e-12 * max(abs(x), 1e-3), (a, b)
    ref_d, got_d = dump_frames(liggghts[deck] / "post" / "dump.txt"), dump_frames(tmp_path / "post" / "dump.txt")
    assert sorted(ref_d) == sorted(got_d)
    if nprocs == 1:
        assert got_d == ref_d
    else:
        for step in ref_d:
            for a, b in zip(ref_d[step], got_d[step]):
                assert a[0] == b[0]
                assert max(abs(x - y) for x, y in zip(a[1:], b[1:])) <= 1e-9, (step, a, b)
