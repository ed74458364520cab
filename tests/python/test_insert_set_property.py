"""fix insert/pack ... set_property NAME V as in LIGGGHTS 3.8 (run live, /usr/bin/liggghts) on
tests/data/liggghts_decks/in.insert_set_property through dembridge-liggghts: the 20 inserted particles get
7.25 in the scalar fix property/atom `tracer`, the particle created before them keeps its default 0.5; every
dumped value, frame by frame, is LIGGGHTS's."""
from dembridge.outputs import read_dump_rows
from liggghts_decks import errors, run_launcher, run_liggghts

DECK = "in.insert_set_property"


def frames(folder):
    return {step: sorted(tuple(r) for r in rows) for step, rows in read_dump_rows(folder / "post" / "dump.txt").items()}


def test_inserted_particles_get_the_property_value_as_in_liggghts(tmp_path):
    rc, lig = run_liggghts(DECK, tmp_path / "liggghts")
    assert rc == 0 and not errors(lig), lig[-2000:]
    rc, out = run_launcher(DECK, tmp_path / "launcher")
    assert rc == 0 and not errors(out), out[-3000:]
    ref, got = frames(tmp_path / "liggghts"), frames(tmp_path / "launcher")
    assert sorted(ref) == [0, 200, 400]
    assert ref[400] == [(1.0, 0.5)] + [(float(i), 7.25) for i in range(2, 22)]  # the deck does set the value
    assert got == ref
