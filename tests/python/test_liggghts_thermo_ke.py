"""thermo ke of a LIGGGHTS deck that inserts into an empty box (tests/data/liggghts_decks/in.thermo_ke, and
in.thermo_ke_dynamic with `compute_modify thermo_temp dynamic yes`), against LIGGGHTS 3.8 run live
(/usr/bin/liggghts).

LIGGGHTS 3.8's ke is its compute thermo_kin_eng (style ke): the sum over the atoms of rmass * (v.v), summed
over the ranks, times 0.5 * mvv2e; its thermo has no temperature keyword (`temp` is an ERROR there). LAMMPS's
ke is the thermo temperature times dof * k_B / 2, with the degrees of freedom counted at setup: 0 atoms
before the insertion, so -0 for the whole run, and with dynamic/dof a value that differs in the last digits.
Through dembridge-liggghts every thermo row is LIGGGHTS's (==) on one rank, and to round-off on two (the
same particles; the sum runs in another order). In a plain lmp run with the plugin the insertion fixes
recount the temperature's degrees of freedom, so LAMMPS's own ke and temp follow the inserted atoms."""
import pytest

from dembridge import thermo_rows
from dembridge.liggghts_deck import translate_text
from dembridge.run import run_deck
from liggghts_decks import DECKS, copy_deck, errors, run_launcher, run_liggghts, warnings

BOLTZ_SI = 1.3806504e-23  # k_B of LAMMPS's units si (its CODATA 2006 value)


def rows(folder):
    log = folder / "log.liggghts" if (folder / "log.liggghts").exists() else folder / "log.lammps"
    return thermo_rows(log)


@pytest.fixture(scope="module", params=["in.thermo_ke", "in.thermo_ke_dynamic"])
def liggghts(request, tmp_path_factory):
    where = tmp_path_factory.mktemp(request.param.replace(".", "_"))
    rc, out = run_liggghts(request.param, where)
    assert rc == 0 and not errors(out), out[-2000:]
    ref = rows(where)
    assert [r[:2] for r in ref] == [(0, 0)] + [(s, 40) for s in range(50, 301, 50)]
    assert ref[0][2] == 0.0 and all(r[2] > 3e-4 for r in ref[1:])  # the real kinetic energy after the insertion
    return request.param, out, ref


def test_thermo_ke_is_liggghts_bit_for_bit_on_one_rank(liggghts, tmp_path):
    deck, lig_out, ref = liggghts
    rc, out = run_launcher(deck, tmp_path)
    assert rc == 0 and not errors(out), out[-3000:]
    assert not warnings(out) - warnings(lig_out)
    assert "KinEng" in (tmp_path / "log.lammps").read_text()  # LIGGGHTS's column name
    assert rows(tmp_path) == ref
    notes = [ln for ln in out.splitlines() if ln.startswith("dembridge-liggghts:") and "thermo_style ... ke" in ln]
    assert len(notes) == 1


@pytest.mark.two_cores
def test_thermo_ke_on_two_ranks_is_liggghts_to_round_off(liggghts, tmp_path):
    deck, _, ref = liggghts
    rc, out = run_launcher(deck, tmp_path, nprocs=2)
    assert rc == 0 and not errors(out), out[-3000:]
    got = rows(tmp_path)
    assert [r[:2] for r in got] == [r[:2] for r in ref]
    assert got[0][2] == 0.0
    for a, b in zip(got[1:], ref[1:]):
        assert abs(a[2] - b[2]) <= 1e-13 * b[2], (a, b)


def test_plain_lmp_ke_and_temp_follow_the_inserted_atoms(tmp_path):
    """The deck translated by the launcher, its thermo asking for LAMMPS's own ke and temp beside the compute
    ke: without dynamic/dof, ke equals the sum of m v^2 / 2 to round-off and temp = 2 ke / ((3N - 3) k_B),
    N = 40 (LAMMPS's definitions, with the degrees of freedom of the atoms there after the insertion)."""
    where = copy_deck("in.thermo_ke", tmp_path)
    box = translate_text((DECKS / "inc.thermo_ke_box").read_text(), "inc.thermo_ke_box", notes=False)
    assert "thermo_kin_eng" not in box.text  # the box part holds no thermo: the ke below is LAMMPS's
    (where / "inc.box.lammps").write_text(box.text)
    (where / "in.lammps").write_text("include inc.box.lammps\ncompute k all ke\n"
                                     "thermo_style custom step atoms ke temp c_k\nthermo 50\n"
                                     "thermo_modify lost ignore norm no format float %.17g\nrun 300\n")
    r = run_deck(str(where / "in.lammps"), cwd=str(where), check=False)
    assert r.returncode == 0, (r.stdout + r.stderr)[-3000:]
    got = rows(where)
    assert [g[:2] for g in got] == [(0, 0)] + [(s, 40) for s in range(50, 301, 50)]
    for step, _, ke, temp, ke_sum in got[1:]:
        assert ke_sum > 3e-4
        assert abs(ke - ke_sum) <= 1e-14 * ke_sum, (step, ke, ke_sum)
        assert abs(temp - 2 * ke_sum / ((3 * 40 - 3) * BOLTZ_SI)) <= 1e-14 * temp, (step, temp)
