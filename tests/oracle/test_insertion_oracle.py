"""fix particletemplate/sphere + particledistribution/discrete + insert/pack, insert/rate/region against
LIGGGHTS 3.8 live.

Each deck of tests/data/liggghts-insertion (LIGGGHTS syntax) runs through /usr/bin/liggghts (one rank)
and, with the two lines LAMMPS spells differently, through LAMMPS + the plugin on 1, 2 and 4 ranks.
Every frame (the insertion steps and the steps after) must hold the same particles: id, type, radius,
mass, x, v, omega compared with == (tolerance 0). The inserted particles must not overlap each other,
the particles there before, or the primitive walls."""
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

import oracle_harness as oh

pytestmark = pytest.mark.two_cores  # 2 and 4 ranks against LIGGGHTS frames that every test shares

DATA = Path(__file__).resolve().parents[1] / "data" / "liggghts-insertion"
DECKS = sorted(p.name[3:] for p in DATA.glob("in.*"))
MESHES = sorted(DATA.glob("*.stl"))  # the insertion faces of the insert/stream decks
COLUMNS = ["type", "radius", "mass", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"]


def lammps_deck(text):
    """The LIGGGHTS deck in LAMMPS spelling: only what LAMMPS itself names differently."""
    text = text.replace("atom_style granular", "atom_style sphere")
    text = text.replace("communicate single vel yes", "comm_modify vel yes")
    text = re.sub(r'dump_modify (\S+) format "', r'dump_modify \1 format line "', text)
    return f"plugin load {oh.plugin_path()}\n" + text


@pytest.fixture(scope="module")
def liggghts_frames(tmp_path_factory):
    out = {}
    for name in DECKS:
        wd = tmp_path_factory.mktemp("lig_" + name)
        case = wd / "case"
        case.mkdir()
        (case / "in.liggghts").write_text((DATA / ("in." + name)).read_text())
        for m in MESHES:
            shutil.copyfile(m, case / m.name)
        out[name] = oh.read_dump(oh.run_liggghts(case, wd / "run"))
    return out


def assert_same_frames(ref, got, label):
    assert sorted(ref) == sorted(got), f"{label}: dumped steps differ"
    for step in sorted(ref):
        a, b = ref[step], got[step]
        assert a.ids.tolist() == b.ids.tolist(), f"{label} step {step}: ids differ ({len(a.ids)} vs {len(b.ids)})"
        for c in COLUMNS:
            bad = np.nonzero(a.columns[c] != b.columns[c])[0]
            assert bad.size == 0, (f"{label} step {step}: {c} differs for id {a.ids[bad[0]]}: "
                                   f"{a.columns[c][bad[0]]!r} vs {b.columns[c][bad[0]]!r}")


def new_particle_gaps(frame, new):
    """Smallest |xi-xj| - (ri+rj) over the pairs with at least one new particle, and the smallest
    distance of a new particle to a box face minus its radius."""
    x = frame["x"]
    r = frame.columns["radius"]
    d = np.sqrt(((x[new][:, None, :] - x[None, :, :]) ** 2).sum(axis=2)) - r[new][:, None] - r[None, :]
    d[np.arange(len(new)), new] = np.inf
    lo = np.array([b[0] for b in frame.box])
    hi = np.array([b[1] for b in frame.box])
    wall = np.min(np.minimum(x[new] - lo[None, :], hi[None, :] - x[new]) - r[new][:, None])
    return d.min(), wall


def assert_no_overlap(frames, label):
    """At each insertion step no new particle touches another particle (new or old) or crosses a face
    of the box (the primitive wall of pack_count_every lies on one)."""
    seen = set()
    for step in sorted(frames):
        f = frames[step]
        new = np.array([k for k, i in enumerate(f.ids.tolist()) if i not in seen], dtype=int)
        seen.update(f.ids.tolist())
        if len(new) == 0:
            continue
        gap, wall = new_particle_gaps(f, new)
        assert gap > 0.0, f"{label} step {step}: overlap {gap}"
        assert wall > 0.0, f"{label} step {step}: a particle crosses the box by {-wall}"


@pytest.mark.liggghts
@pytest.mark.plugin
@pytest.mark.parametrize("name", DECKS)
def test_insertion_bit_identical_one_rank(name, liggghts_frames, tmp_path):
    deck = (DATA / ("in." + name)).read_text()
    got = oh.read_dump(oh.run_lammps(lammps_deck(deck), tmp_path, files=MESHES))
    assert_same_frames(liggghts_frames[name], got, name)
    assert max(len(f.ids) for f in got.values()) > 0
    if "no_overlapcheck" not in name:
        assert_no_overlap(got, name)


@pytest.mark.liggghts
@pytest.mark.plugin
@pytest.mark.parametrize("name,nprocs", [("pack_volfrac_two_templates", 2), ("pack_count_every", 2),
                                         ("pack_mass_three_templates", 4),
                                         ("rate_region_two_templates", 2),
                                         ("stream_extrude_two_templates", 2),
                                         ("stream_mass_every_all_in", 2), ("stream_no_overlapcheck_uniform", 4),
                                         ("stream_parallel_cut_box", 2)])
def test_insertion_rank_invariant(name, nprocs, liggghts_frames, tmp_path):
    """On 2 and 4 ranks the plugin inserts LIGGGHTS's one-rank particles (LIGGGHTS itself does not)."""
    deck = (DATA / ("in." + name)).read_text()
    got = oh.read_dump(oh.run_lammps(lammps_deck(deck), tmp_path, nprocs=nprocs, files=MESHES))
    assert_same_frames(liggghts_frames[name], got, f"{name} on {nprocs} ranks")


@pytest.mark.liggghts
@pytest.mark.plugin
def test_stream_release_state_survives_sorting_and_migration(liggghts_frames, tmp_path):
    """insert/stream keeps, per atom, where and when each particle entered the extrusion volume; LAMMPS
    sorts the atoms every 3 steps here, and the 2 ranks meet at z = 0.085, inside the extrusion volume (0.08 to
    0.1), so the particles migrate while in it: the state must follow its atom for them to stay LIGGGHTS's."""
    name = "stream_no_overlapcheck_uniform"
    deck = lammps_deck((DATA / ("in." + name)).read_text())
    deck = deck.replace("atom_modify map array", "atom_modify map array sort 3 0.004\nprocessors 1 1 2")
    deck = deck.replace("create_box 1 reg", "create_box 1 reg\nbalance 1.0 z 0.95")
    got = oh.read_dump(oh.run_lammps(deck, tmp_path, nprocs=2, files=MESHES))
    assert_same_frames(liggghts_frames[name], got, f"{name} sorted, 2 ranks")
