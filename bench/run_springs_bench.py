#!/usr/bin/env python3
"""Springs benchmark of issue 5 (acceptance E): cost per spring-step of fix parmec/spring on the
"Parmec spring baseline" lattice of ../shared/bench/README.md, on 1 and 2 MPI ranks, against the
published Parmec figures (ns per spring-step, 1 core / 2 threads).

Scenario (as the README): nx*ny*nz lattice, spacing 1, particles of mass 1 (atom_style sphere, centre
springs, so the inertia does not enter), no contact law; FOLLOWER springs between the centres of +x, +y,
+z neighbours; every top particle tied to the fixed point 1 above it (part2 = -1); spring table
[-1,-2e4,-0.01,-1e2,0.01,1e2,1,2e4], dashpot = critical ratio 0.05, gravity (0,0,-10), random initial
velocities in [-0.5, 0.5] m/s, h = 2e-4 s, no output while timing (thermo only at the end).
Sizes: 14x16x16 (3584 atoms, 10272 springs) and 32x32x33 (33792 atoms, 99264 springs).

Measure: LAMMPS 'Loop time' of --steps steps (after a 'run 0' setup), best and median of --rounds
interleaved rounds; ns per spring-step = loop time / (steps * springs). On a shared machine the wall
time includes waiting for a core: the "CPU-time" figure multiplies it by LAMMPS's '% CPU use' of the
loop (capped at 100 %), i.e. the loop time the ranks would need with a core each. The fix's per-step work
includes the EQM of every spring (ratio dashpot and the local output column) and the ordered
reverse communication of ghost contributions.

usage: /work/main/.venv/bin/python bench/run_springs_bench.py [--steps 200] [--rounds 3] [--plugin PATH]
       [--sizes 1e4,1e5] [--ranks 1,2]
Outputs: bench/out/springs/results.md and runs.csv (git-ignored), and the table on stdout.
"""
import argparse
import datetime
import os
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
VENV = os.path.join(REPO, ".venv")
OUT = os.path.join(HERE, "out", "springs")

SIZES = {"1e4": (14, 16, 16), "1e5": (32, 32, 33)}
# Parmec, ns per spring-step, follower + ratio dashpot, median of 10 runs: (1 core, 2 threads)
PARMEC = {"1e4": (98.0, 52.0), "1e5": (216.0, 83.0)}


def write_springs(path, nx, ny, nz):
    """Definitions file: atom id = 1 + i + nx*(j + ny*k); returns the number of springs."""
    aid = lambda i, j, k: 1 + i + nx * (j + ny * k)  # noqa: E731
    n = 0
    with open(path, "w") as f:
        f.write("table K -1 -2e4 -0.01 -1e2 0.01 1e2 1 2e4\n")
        for k in range(nz):
            for j in range(ny):
                for i in range(nx):
                    a = aid(i, j, k)
                    for (di, dj, dk) in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
                        if i + di < nx and j + dj < ny and k + dk < nz:
                            n += 1
                            f.write(f"spring {n} {a} centre {aid(i + di, j + dj, k + dk)} centre K ratio 0.05\n")
                    if k == nz - 1:
                        n += 1
                        f.write(f"spring {n} {a} centre -1 {i} {j} {k + 1} K ratio 0.05\n")
    return n


def deck(path, springs_file, nx, ny, nz, steps, plugin):
    lines = [
        f"plugin load {plugin}",
        "units si", "atom_style sphere", "boundary m m m", "atom_modify map array",
        "comm_modify vel yes cutoff 2.5", "neighbor 0.3 bin", "neigh_modify every 10 delay 0 check yes",
        f"lattice sc 1.0", f"region box block -0.5 {nx - 0.5} -0.5 {ny - 0.5} -0.5 {nz - 0.5} units box",
        "create_box 1 box", "create_atoms 1 region box",
        "set group all diameter 0.5", "set group all mass 1.0",
        "variable vx atom random(-0.5,0.5,4711)", "variable vy atom random(-0.5,0.5,4712)",
        "variable vz atom random(-0.5,0.5,4713)", "velocity all set v_vx v_vy v_vz",
        f"fix S all parmec/spring file {springs_file}",
        "fix I all nve/sphere", "fix G all gravity 10.0 vector 0 0 -1", "timestep 2e-4",
        "thermo 0", "run 0", f"run {steps}",
    ]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def loop_time(log):
    """(wall loop time, CPU share) of the last run: LAMMPS's 'Loop time' and '% CPU use' (CPU time of
    the loop / wall time, averaged over ranks)."""
    m = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps", log)
    c = re.findall(r"([0-9.]+)% CPU use with", log)
    if not m or not c:
        raise RuntimeError("no 'Loop time' / '% CPU use' in the log:\n" + log[-2000:])
    return float(m[-1][0]), float(c[-1]) / 100.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--sizes", default="1e4,1e5")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--plugin", default=os.environ.get("DEMBRIDGE_PLUGIN", os.path.join(REPO, "build", "dembridgeplugin.so")))
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    lmp, mpiexec = os.path.join(VENV, "bin", "lmp"), os.path.join(VENV, "bin", "mpiexec")
    sizes, ranks = a.sizes.split(","), [int(r) for r in a.ranks.split(",")]
    nspr = {}
    for s in sizes:
        nx, ny, nz = SIZES[s]
        nspr[s] = write_springs(os.path.join(OUT, f"lattice_{s}.springs"), nx, ny, nz)
        deck(os.path.join(OUT, f"in.lattice_{s}"), os.path.join(OUT, f"lattice_{s}.springs"), nx, ny, nz, a.steps, a.plugin)
    times = {(s, r): [] for s in sizes for r in ranks}
    cpus = {(s, r): [] for s in sizes for r in ranks}
    runs = ["size,ranks,round,springs,steps,loop_s,cpu_share,ns_per_spring_step,ns_cpu"]
    for rnd in range(a.rounds):  # interleaved rounds: load drift hits every configuration alike
        for s in sizes:
            for r in ranks:
                cmd = [lmp, "-in", os.path.join(OUT, f"in.lattice_{s}"), "-log", "none", "-screen", "none", "-nocite"]
                logf = os.path.join(OUT, f"log.{s}.{r}")
                cmd[cmd.index("-log") + 1] = logf
                if r > 1:
                    cmd = [mpiexec, "-n", str(r)] + cmd
                p = subprocess.run(cmd, cwd=OUT, capture_output=True, text=True)
                log = open(logf).read() if os.path.exists(logf) else ""
                if p.returncode != 0:
                    sys.exit(f"run failed ({s}, {r} ranks):\n{p.stdout}{p.stderr}{log[-3000:]}")
                t, share = loop_time(log)
                ns = t / (a.steps * nspr[s]) * 1e9
                times[s, r].append(ns)
                cpus[s, r].append(ns * min(share, 1.0))
                runs.append(f"{s},{r},{rnd},{nspr[s]},{a.steps},{t:.6g},{share:.3f},{ns:.4g},{ns * min(share, 1.0):.4g}")
                print(f"round {rnd}: {s} ({nspr[s]} springs), {r} rank(s): {ns:.1f} ns per spring-step "
                      f"(CPU share {share:.2f}: {ns * min(share, 1.0):.1f} ns of CPU time per rank)", flush=True)
    with open(os.path.join(OUT, "runs.csv"), "w") as f:
        f.write("\n".join(runs) + "\n")
    up = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    md = [f"fix parmec/spring lattice benchmark, {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, {a.steps} steps, "
          f"{a.rounds} rounds; uptime: {up}", "",
          "| springs | ranks | wall ns per spring-step (best / median) | CPU-time ns (best / median) | "
          "Parmec (1 core / 2 threads) | ratio wall best / Parmec | ratio CPU best / Parmec |",
          "|---|---|---|---|---|---|---|"]
    for s in sizes:
        for r in ranks:
            best, med = min(times[s, r]), statistics.median(times[s, r])
            cb, cm = min(cpus[s, r]), statistics.median(cpus[s, r])
            ref = PARMEC[s][0 if r == 1 else 1]
            md.append(f"| {nspr[s]} | {r} | {best:.1f} / {med:.1f} | {cb:.1f} / {cm:.1f} | {ref:.0f} | "
                      f"{best / ref:.2f} | {cb / ref:.2f} |")
    text = "\n".join(md)
    with open(os.path.join(OUT, "results.md"), "w") as f:
        f.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
