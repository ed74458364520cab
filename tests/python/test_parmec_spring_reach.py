"""Springs longer than the ghost cutoff: the spring fix raises the cutoff when a spring outgrows it, so that
part2 stays a ghost of part1's owner on every decomposition (doc/fix_parmec_spring.md "Parallel")."""
import math
import os
import re

import pytest

from dembridge.outputs import read_dump_by_id
from dembridge.parmec import run_script
from lmp_runs import run_lmp

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, "..", "data", "parmec", "scripts")
N = 9          # atoms of the chain, 1 m apart on x = 0..8
CUT = 1.5      # the deck's ghost cutoff: the initial springs (1 m) fit, the stretched ones do not
STEPS = 200    # 2 s at 10 ms (few steps: 4 ranks oversubscribe a 2-core machine)
RAISED = re.compile(r"spring (\d+) between atoms (\d+) and (\d+) is (\S+) long, beyond the ghost cutoff (\S+): "
                    r"ghost cutoff raised to (\S+)")


def chain_head(cutoff=CUT):
    return ["units si", "atom_style sphere", "boundary s s s", "atom_modify map array",
            f"comm_modify vel yes cutoff {cutoff}", "processors * 1 1", "neighbor 0.3 bin"]


def chain_fixes():
    """Nine 4.2 kg spheres tied in a row (springs 2..9 between neighbours, 1 and 10 to space at the ends), 50 N/m
    with a light dashpot, under gravity; UNSPRING cuts spring 5 (atoms 4-5) when its SF exceeds 30 N: the halves
    swing down from their anchors and their top springs stretch to over three times their length."""
    spr = ["table K -30 -1500 30 1500", "table D -1 -5 1 5", "spring 1 1 centre -1 0 0 0 K dashpot D",
           f"spring {N + 1} {N} centre -1 {N - 1} 0 0 K dashpot D"]
    spr += [f"spring {s} {s - 1} centre {s} centre K dashpot D" for s in range(2, N + 1)]
    return ["fix S all parmec/spring " + " ".join(spr),
            "fix U all parmec/unspring S rule tsprings 5 msprings 5 limits None 30 abs",
            "fix G all gravity 9.81 vector 0 0 -1", "fix I all nve", "timestep 1e-2"]


def chain_deck(tmp, steps=STEPS, restart_at=None):
    lines = chain_head() + ["region box block -1 9 -1 1 -1 1", "create_box 1 box"]
    lines += [f"create_atoms 1 single {i} 0 0 units box" for i in range(N)]
    lines += ["set group all diameter 0.2 density 1000"] + chain_fixes()
    lines += [f"dump A all custom 10 {tmp}/atom.dump id x y z vx vy vz", "dump_modify A sort id format float %.17g",
              f"dump L all local {steps} {tmp}/loc.dump f_S[1] f_S[2] f_S[3] f_S[4] f_S[5] f_S[6] f_S[7]",
              "dump_modify L format float %.17g"]
    if restart_at:
        return lines + [f"run {restart_at}", f"write_restart {tmp}/chain.restart"]
    return lines + [f"run {steps}"]


def restart_deck(tmp, src, steps):
    """Reads the chain at step `restart_at` with the deck's small cutoff again: the set-up must raise it."""
    head = chain_head()
    return ([f"read_restart {src}/chain.restart", head[4], head[6]] + chain_fixes() +
            [f"dump A all custom {STEPS} {tmp}/atom.dump id x y z vx vy vz",
             "dump_modify A sort id format float %.17g", f"run {steps}"])


def slab_changes(dump, n):
    """Atoms whose slab of an n x 1 x 1 grid (the shrink-wrapped box's x range split evenly) changed between
    dump frames: each change moved the atom, with its spring states, to another rank."""
    seen, changes = {}, 0
    lines = open(dump).read().split("ITEM: TIMESTEP")[1:]
    for frame in lines:
        rows = frame.splitlines()
        b = rows.index("ITEM: BOX BOUNDS ss ss ss")
        lo, hi = map(float, rows[b + 1].split()[:2])
        for r in rows[rows.index(next(x for x in rows if x.startswith("ITEM: ATOMS"))) + 1:]:
            a, x = int(r.split()[0]), float(r.split()[1])
            slab = min(n - 1, int(n * (x - lo) / (hi - lo)))
            changes += a in seen and seen[a] != slab
            seen[a] = slab
    return changes


def spring_lengths(frame):
    """Centre distances of the springs between atoms (id: length) in one dump frame {id: [x y z vx vy vz]}."""
    return {s: math.dist(frame[s - 1][:3], frame[s][:3]) for s in range(2, N + 1)}


@pytest.mark.two_cores
def test_chain_beyond_the_ghost_cutoff_1_2_4_ranks_and_restart(tmp_path):
    """The chain on 1, 2 and 4 ranks (x split into slabs: the halves' atoms change rank as they swing): every run
    reaches 2 s (before, each stopped with 'longer than the ghost cutoff' once a spring passed 1.5 m), the
    springs stretch to over 3x their length, the cutoff is raised the same way on every decomposition and the
    trajectories and spring outputs are bitwise equal (tolerance 0: the forces are summed in spring order and the
    ghosts carry the owners' doubles); a restart at 1 s read with the small cutoff again continues bitwise."""
    runs = {}
    for n in (1, 2, 4):
        d = tmp_path / f"np{n}"
        d.mkdir()
        log = run_lmp(d, chain_deck(d), n)
        atoms, loc = read_dump_by_id(d / "atom.dump"), read_dump_by_id(d / "loc.dump")
        runs[n] = (atoms, loc[STEPS], [m.groups() for m in RAISED.finditer(log)])
    atoms, loc, raised = runs[1]
    assert max(atoms) == STEPS
    longest = max(max(spring_lengths(f).values()) for f in atoms.values())
    print(f"[reach] chain: longest spring {longest:.3f} m (initial 1 m, cutoff {CUT}); cutoff raised "
          f"{len(raised)} times: {[(r[0], r[3], r[5]) for r in raised]}; SS of spring 5 {loc[5][5]}")
    assert longest > 3.0 * 1.0 and longest > 2 * CUT
    assert loc[5][5] == -1.0  # UNSPRING removed it
    assert len(raised) >= 2 and float(raised[-1][5]) > 3.0
    for n in (2, 4):
        assert runs[n][0] == atoms, n
        assert runs[n][1] == loc and runs[n][2] == raised, n
    slabs = slab_changes(tmp_path / "np4" / "atom.dump", 4)
    print(f"[reach] atoms that changed rank on 4 ranks: {slabs}")
    assert slabs >= 2  # the spring states migrated with their atoms

    # restart: write at 1 s (springs already past the deck's cutoff), read with 'cutoff 1.5' again
    src, cont = tmp_path / "first", tmp_path / "second"
    src.mkdir(), cont.mkdir()
    run_lmp(src, chain_deck(src, restart_at=STEPS // 2), 2)
    log = run_lmp(cont, restart_deck(cont, src, STEPS // 2), 2)
    setup = [m.groups() for m in RAISED.finditer(log)]
    assert setup and float(setup[0][3]) > CUT  # raised at the set-up, before the first borders
    assert read_dump_by_id(cont / "atom.dump")[STEPS] == atoms[STEPS]


def test_unspring_activate_model_runs_to_2s(tmp_path):
    """The Parmec model that stopped at t = 1.37 s ('spring 48 ... is 3.00009 long, longer than the ghost cutoff
    3'), through the front end: the cutoff it starts with (3 m) is raised as the removed springs' ends part, and
    DEM reaches 2 s. The first five cubes come to rest on the plane z = -5 (centres at -4.5, held by the
    activated springs), the others hang from space; the removed spring 48 ends 4.9 m long. Parmec's step
    (0.05 CRITICAL, 97 960 steps), HISTORY every 0.01 s (every step would triple the run time)."""
    ns = run_script(os.path.join(SCRIPTS, "unspring_activate.py"), ["0.05", "2.0", "0.01"], workdir=str(tmp_path))
    H = ns["H"]
    assert len(H["TIME"]) == 200 and H["TIME"][-1] > 1.98  # rows at 0, 0.01, ..., 1.99; DEM returned at 2 s
    print(f"[reach] unspring_activate: removed spring 48 {max(H['LEN_cut']):.3f} m long at most; PZ0 {H['PZ0'][-1]:.4f}, "
          f"PZ4 {H['PZ4'][-1]:.4f}, PZ9 {H['PZ9'][-1]:.4f}")
    assert H["SS_cut"][-1] == -1.0 and max(H["LEN_cut"]) > 3.0 * 1.5
    assert abs(H["PZ0"][-1] + 4.5) < 0.01 and abs(H["PZ4"][-1] + 4.5) < 0.01
    assert 0.4 < H["PZ9"][-1] < 0.5


@pytest.mark.two_cores
def test_long_spring_and_torsion_at_setup_1_2_ranks(tmp_path):
    """A spring and a torsion spring between atoms 5 m apart with a ghost cutoff of 1 (before: an ERROR at the
    set-up, 'longer than the ghost cutoff' / 'farther than the ghost cutoff'): the set-up raises the cutoff to
    10 m once per fix (the torsion fix finds it raised already), and 1 and 2 ranks (part2 then a ghost) give
    bitwise equal atoms after 200 steps."""
    out = {}
    for n in (1, 2):
        d = tmp_path / f"np{n}"
        d.mkdir()
        log = run_lmp(d, [
            "units si", "atom_style bpm/sphere", "boundary f f f", "atom_modify map array",
            "comm_modify vel yes cutoff 1", "processors * 1 1", "region box block -2 8 -2 2 -2 2", "create_box 1 box",
            "create_atoms 1 single 0 0 0 units box", "create_atoms 1 single 5 0 0 units box",
            "set group all diameter 0.5 density 100", "velocity all set 0 0.1 0 units box", "set atom 2 omega 0 0 1",
            "fix S all parmec/spring table K -10 -1e3 10 1e3 spring 1 1 centre 2 centre K",
            "fix T all parmec/torsion table R -1 10 1 -10 torsion 3 1 2 0 0 1 1 0 0 kroll R kpitch R kyaw R",
            "fix I all nve/bpm/sphere", "timestep 1e-3",
            f"dump A all custom 200 {d}/atom.dump id x y z vx vy vz omegax omegay omegaz",
            "dump_modify A sort id format float %.17g", "run 200"], n)
        raised = [m.groups() for m in RAISED.finditer(log)]
        assert [r[:3] for r in raised] == [("1", "1", "2")], log[-2000:]
        assert float(raised[0][3]) == 5.0 and float(raised[0][5]) == 10.0
        out[n] = read_dump_by_id(d / "atom.dump")[200]
    assert out[2] == out[1]
    assert out[1][2][8] < 0.99  # the torsion spring acted: atom 2's spin about z (1 rad/s at the start) slowed
