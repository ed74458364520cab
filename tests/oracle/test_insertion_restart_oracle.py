"""Insertion across a restart against LIGGGHTS 3.8 live (one rank).

Three decks of tests/data/liggghts-insertion (insert/pack every 1000 steps with vel uniform,
insert/rate/region with two templates, insert/stream with extrude_length and two templates) are
split at a step between two insertions (the stream's particles still in the extrusion volume):
`run R` + write_restart, then a new process: read_restart, the fixes defined again, run to the end.
* Ours, split so, inserts and moves exactly what an uninterrupted LIGGGHTS run does: every frame
  after the restart (id, type, radius, mass, x, v, omega) equals LIGGGHTS's uninterrupted run (==).
* LIGGGHTS 3.8 split the same way does not: it reseeds the region's stream (insert/pack,
  insert/rate/region) or restarts the face's stream and redraws the extrusion share (insert/stream)
  after read_restart, so its next insertion after the restart puts the particles elsewhere than its
  own uninterrupted run (run for the insert/pack and insert/stream decks) (the measured behaviour doc/fix_insert_pack.md and doc/fix_insert_stream.md
  describe)."""
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

import oracle_harness as oh

DATA = Path(__file__).resolve().parents[1] / "data" / "liggghts-insertion"
COLUMNS = ["type", "radius", "mass", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"]
# deck, restart step (between two insertions), whether LIGGGHTS is split too (insert/rate/region
# reseeds the region's stream as insert/pack does)
CASES = [("pack_count_every", 1500, True), ("rate_region_two_templates", 250, False),
         ("stream_extrude_two_templates", 215, True)]
# what the restart file holds and read_restart defines again
SETUP = ("atom_style", "atom_modify", "boundary", "units", "create_box", "pair_style", "pair_coeff", "region reg ")


def split_deck(text, r):
    """The deck as `run R` + write_restart, and as read_restart + the rest of the run."""
    total = int(re.search(r"^run (\d+)", text, re.M).group(1))
    first = re.sub(r"^run \d+", f"run {r}\nwrite_restart ins.restart", text, flags=re.M)
    body = [l for l in text.splitlines() if not l.startswith(SETUP)]
    second = re.sub(r"^run \d+", f"run {total - r}", "read_restart ins.restart\n" + "\n".join(body) + "\n", flags=re.M)
    return first, second


def lammps_deck(text):
    """LAMMPS spelling of the two lines LAMMPS names differently, and the plugin loaded first."""
    text = text.replace("atom_style granular", "atom_style sphere")
    text = text.replace("communicate single vel yes", "comm_modify vel yes")
    text = re.sub(r'dump_modify (\S+) format "', r'dump_modify \1 format line "', text)
    return f"plugin load {oh.plugin_path()}\n" + text


def new_particles(frames, restart):
    """{step: ids first seen in that frame} for the frames after the restart (ids dumped at or before
    the restart are not new)."""
    seen = set()
    for s in sorted(frames):
        if s <= restart:
            seen.update(frames[s].ids.tolist())
    out = {}
    for s in sorted(frames):
        if s > restart:
            ids = [i for i in frames[s].ids.tolist() if i not in seen]
            if ids:
                out[s] = ids
            seen.update(ids)
    return out


def first_difference(ref, got, new):
    """The first (step, id, column) where a particle inserted after the restart differs at its insertion
    frame (ref and got hold the same ids), None if none does."""
    for s, ids in sorted(new.items()):
        a, b = ref[s], got[s]
        if a.ids.tolist() != b.ids.tolist():
            return s, None, "ids"
        rows = np.nonzero(np.isin(a.ids, ids))[0]
        for c in COLUMNS:
            bad = rows[a.columns[c][rows] != b.columns[c][rows]]
            if bad.size:
                return s, int(a.ids[bad[0]]), c
    return None


@pytest.mark.parametrize("name,restart,split_liggghts", CASES)
def test_restarted_run_inserts_what_liggghts_uninterrupted_run_does(tmp_path, name, restart, split_liggghts):
    text = (DATA / f"in.{name}").read_text()
    case = tmp_path / "case"
    case.mkdir()
    (case / "in.liggghts").write_text(text)
    meshes = sorted(DATA.glob("*.stl"))
    for m in meshes:
        shutil.copyfile(m, case / m.name)
    full = oh.read_dump(oh.run_liggghts(case, tmp_path / "lig_full"))
    new = new_particles(full, restart)
    assert len(new) >= 1 and sum(len(v) for v in new.values()) >= 10, f"{name}: too few insertions after the restart"
    first, second = split_deck(text, restart)

    ours_first = tmp_path / "ours_first"
    oh.run_lammps(lammps_deck(first), ours_first, files=meshes)
    ours = oh.read_dump(oh.run_lammps(lammps_deck(second), tmp_path / "ours_second",
                                      files=meshes + [ours_first / "ins.restart"]))
    after = sorted(s for s in full if s > restart)
    assert sorted(ours) == after
    for s in after:  # the same particles in every frame
        assert ours[s].ids.tolist() == full[s].ids.tolist(), f"{name} step {s}: ids differ"
    bad = first_difference(full, ours, new)
    assert bad is None, f"{name}: particle {bad[1]} inserted at step {bad[0]} after the restart differs ({bad[2]})"

    if not split_liggghts:
        return
    oh.run_liggghts(case, tmp_path / "lig_first", deck_text=first)
    lig = oh.read_dump(oh.run_liggghts(tmp_path / "lig_first", tmp_path / "lig_second", deck_text=second))
    bad = first_difference(full, lig, new)
    # LIGGGHTS's own restart: already its first insertion after the restart differs
    assert bad is not None and bad[0] == min(new), f"{name}: LIGGGHTS's restarted run: {bad}"
