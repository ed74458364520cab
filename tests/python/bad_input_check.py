"""One bad-input case: the deck's lines end in a LAMMPS ERROR whose text holds every fragment (the command,
the argument, what was expected). Shared by the parametrised bad-input tests of the LIGGGHTS fixes."""
from test_bad_input import run_deck


def assert_error(name, lines, fragments):
    msg = run_deck(lines)
    assert msg is not None and "ERROR" in msg, f"{name}: no ERROR"
    for f in fragments:
        assert f in msg, f"{name}: {f!r} not in {msg!r}"
