#!/usr/bin/env python3
"""Memory and time per atom on the dense periodic fcc bed (bench/in.bed.lammps, bench/in.bed.liggghts): every
sphere in 12 contacts with tangential history, 4 n^3 spheres. In one invocation, for each size and configuration:

  peak RSS per atom      the sum over the run's LAMMPS (or LIGGGHTS) processes of their peak resident set
                         (VmHWM, polled from /proc every 50 ms; exact for one rank, where it only rises),
                         divided by the atom count;
  memory line            LAMMPS's "Per MPI rank memory allocation" (avg x ranks; LIGGGHTS's "Memory usage
                         per processor"), per atom;
  line / RSS growth      (memory line at this size - at the smallest size) / (peak RSS at this size - at the
                         smallest size): how much of the memory that grows with the atoms the line accounts for
                         (target: within 10 % of 1 for LAMMPS + the plugin);
  ns per atom-step       Loop time / (atoms x steps), and the MD loop's CPU time per atom-step (/proc, from the
                         thermo header to 'Loop time'), which time-slicing on a loaded machine hardly changes.

The target (M1): the plugin's peak RSS per atom at 10^6 atoms <= the built-in's (gran/hooke/history,
gran/hertz/history), in LAMMPS numeric syntax and in LIGGGHTS 2.x material syntax (plugin only: compared with
the built-in hertz). The LIGGGHTS 3.8 twins (lig_*) are not run by default: LIGGGHTS 3.8 creates another number of
atoms from the same lattice and region (37044 instead of 97556 at n = 29, and the bed then explodes), which the
script refuses (it checks every run's atom count); not investigated further. The thermo output
of plugin and built-in (numeric syntax) must be identical: exit status 1 otherwise.

usage: .venv/bin/python bench/run_bed_memory_bench.py [--sizes 1e4,1e5,1e6] [--ranks 1] [--only k1,k2]
           [--plugin build/dembridgeplugin.so] [--atom-steps 2e7] [--no-liggghts] [--out DIR]
  --sizes 1e7 --ranks 2 --only lmp_hooke,plg_hooke   the scale run (10^7 spheres, ~10 GB, 20 steps)
Every run is a separate process; the steps of a run are max(20, atom-steps / atoms) (20 at 10^6), rebuilding
the neighbour list every 10 steps. 10^4-10^6, the 5 LAMMPS configurations: ~5 min and 1 GB at a time on 2 idle
cores (20 min at a load of 22).
"""
import argparse
import os
import re
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import run_chute_bench as chute  # noqa: E402  (run_timed, descendants, parse_log, parse_memory)
import run_hopper_bench as hopper  # noqa: E402  (raw_lmp, env_of: the wheel's binary and its MPICH)

CELLS = {"1e4": 14, "1e5": 29, "1e6": 63, "1e7": 136}  # fcc cells per side: 4 n^3 = 10976, 97556, 1000188, 10061824
CONFIGS = {  # key: (code, model, plugin, reference for M1)
    "lmp_hooke": ("lammps", "hooke", False, None),
    "plg_hooke": ("lammps", "hooke", True, "lmp_hooke"),
    "lmp_hertz": ("lammps", "hertz", False, None),
    "plg_hertz": ("lammps", "hertz", True, "lmp_hertz"),
    "plg_hertz2x": ("lammps", "hertz2x", True, "lmp_hertz"),
    "lig_hooke": ("liggghts", "hooke", False, None),
    "lig_hertzmat": ("liggghts", "hertzmat", False, None),
}
SAME_PHYSICS = [("plg_hooke", "lmp_hooke"), ("plg_hertz", "lmp_hertz")]
MPIEXEC = os.path.join(chute.VENV, "bin", "mpiexec")
OMPI_RUN = ["/usr/bin/mpirun", "--allow-run-as-root", "--bind-to", "none", "-np"]


class PeakRss:
    """Polls the peak resident set (VmHWM) of every LAMMPS/LIGGGHTS process under a root pid."""

    NAMES = ("lmp", "liggghts")

    def __init__(self, period=0.05):
        self.period, self.peak = period, {}
        self._done = threading.Event()

    def start(self, pid):
        self._thread = threading.Thread(target=self._poll, args=(pid,), daemon=True)
        self._thread.start()

    def stop(self):
        self._done.set()
        self._thread.join()

    def _poll(self, root):
        while not self._done.is_set():
            for pid in chute.descendants(root):
                try:
                    with open(f"/proc/{pid}/status") as fh:
                        status = fh.read()
                except OSError:
                    continue
                name = re.search(r"^Name:\s*(\S+)", status, re.M)
                hwm = re.search(r"^VmHWM:\s*(\d+) kB", status, re.M)
                if name and hwm and name.group(1) in self.NAMES:
                    self.peak[pid] = max(self.peak.get(pid, 0), int(hwm.group(1)) * 1024)
            self._done.wait(self.period)

    def total(self):
        return sum(self.peak.values())


def natoms(size):
    return 4 * CELLS[size] ** 3


def command(key, size, nsteps, nranks, log, plugin):
    code, model, use_plugin, _ = CONFIGS[key]
    common = ["-var", "n", str(CELLS[size]), "-var", "model", model, "-var", "nsteps", str(nsteps), "-log", log]
    if code == "liggghts":
        cmd = ["stdbuf", "-o0", chute.LIGGGHTS, "-in", "in.bed.liggghts"] + common  # unbuffered: the loop CPU window
        return (OMPI_RUN + [str(nranks)] + cmd) if nranks > 1 else cmd
    cmd = [hopper.raw_lmp(), "-in", "in.bed.lammps", "-nocite"] + common
    if use_plugin:
        cmd += ["-var", "useplugin", "1", "-var", "plugin", plugin]
    return ([MPIEXEC, "-n", str(nranks)] + cmd) if nranks > 1 else cmd


def run_one(key, size, nsteps, nranks, outdir, plugin):
    tag = f"{key}_{size}_{nranks}r"
    log, screen = os.path.join(outdir, f"log.{tag}"), os.path.join(outdir, f"screen.{tag}")
    peak = PeakRss()
    load = chute.loadavg()
    rc, elapsed, _, loop_cpu = chute.run_timed(["nice", "-n", "5"] + command(key, size, nsteps, nranks, log, plugin), screen,
                                               env=hopper.env_of(CONFIGS[key][0]), timeout=7200, monitor=peak)
    loop, _, rows, err = chute.parse_log(log)
    if rc != 0 or err:
        raise RuntimeError(f"{tag}: exit status {rc} {err[:1]} (see {screen})")
    line_mb, _ = chute.parse_memory(log)
    n = natoms(size)
    if not rows or int(rows[0][1]) != n:  # thermo column 2 is the atom count
        raise RuntimeError(f"{tag}: {rows[0][1] if rows else 'no'} atoms created, expected {n} (see {log})")
    return {"key": key, "size": size, "ranks": nranks, "atoms": n, "steps": nsteps, "rss": peak.total(),
            "line": line_mb * 1024 * 1024 * nranks, "loop": loop, "loop_cpu": loop_cpu, "elapsed": elapsed, "load": load,
            "thermo": rows}


def table(results, sizes):
    print("| configuration | atoms | ranks | peak RSS B/atom | memory line B/atom | line / RSS growth | vs reference "
          "(RSS) | ns/atom-step wall | CPU | load |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in results:
        base = next((b for b in results if b["key"] == r["key"] and b["ranks"] == r["ranks"] and b["size"] == sizes[0]), None)
        growth = "-"
        if base is not None and r is not base and r["rss"] > base["rss"]:
            growth = f"{(r['line'] - base['line']) / (r['rss'] - base['rss']):.3f}"
        ref = CONFIGS[r["key"]][3]
        refrun = next((b for b in results if b["key"] == ref and b["size"] == r["size"] and b["ranks"] == r["ranks"]), None)
        vs = f"{r['rss'] / refrun['rss']:.3f} of {ref}" if refrun else "-"
        per = 1e9 / (r["atoms"] * r["steps"])
        print(f"| {r['key']} | {r['atoms']:,} | {r['ranks']} | {r['rss'] / r['atoms']:.1f} | {r['line'] / r['atoms']:.1f} | "
              f"{growth} | {vs} | {r['loop'] * per:.1f} | {r['loop_cpu'] * per:.1f} | {r['load']:.1f} |")


def verdicts(results):
    ok = True
    for r in results:
        ref = CONFIGS[r["key"]][3]
        refrun = next((b for b in results if b["key"] == ref and b["size"] == r["size"] and b["ranks"] == r["ranks"]), None)
        if refrun and r["size"] == "1e6":
            print(f"M1 {r['key']} at {r['atoms']:,} atoms: {r['rss'] / r['atoms']:.1f} B/atom vs {ref} "
                  f"{refrun['rss'] / refrun['atoms']:.1f}: " + ("met" if r["rss"] <= refrun["rss"] else "NOT met"))
    for plg, ref in SAME_PHYSICS:
        for r in results:
            b = next((b for b in results if b["key"] == ref and b["size"] == r["size"] and b["ranks"] == r["ranks"]), None)
            if r["key"] == plg and b and r["thermo"] != b["thermo"]:
                print(f"thermo of {plg} differs from {ref} at {r['size']}, {r['ranks']} ranks")
                ok = False
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="1e4,1e5,1e6", help="comma-separated subset of " + ",".join(CELLS))
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--only", default=",".join(k for k in CONFIGS if CONFIGS[k][0] == "lammps"),
                    help="comma-separated subset of " + ",".join(CONFIGS))
    ap.add_argument("--no-liggghts", action="store_true")
    ap.add_argument("--atom-steps", type=float, default=2e7, help="atom-steps per run (at least 20 steps)")
    ap.add_argument("--plugin", default=os.path.join(chute.REPO, "build", "dembridgeplugin.so"))
    ap.add_argument("--out", default=os.path.join(HERE, "out", "bed"))
    args = ap.parse_args()
    sizes, args.out = args.sizes.split(","), os.path.abspath(args.out)  # the runs start in bench/
    keys = args.only.split(",")
    if any(s not in CELLS for s in sizes) or any(k not in CONFIGS for k in keys):
        sys.exit(f"--sizes from {','.join(CELLS)}, --only from {','.join(CONFIGS)}")
    if args.no_liggghts or not os.path.exists(chute.LIGGGHTS):
        keys = [k for k in keys if CONFIGS[k][0] != "liggghts"]
    os.makedirs(args.out, exist_ok=True)
    plugin = os.path.join(args.out, "dembridgeplugin.so")  # a copy: a rebuild during the run changes nothing
    subprocess.run(["cp", args.plugin, plugin], check=True)
    print("start:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip(), flush=True)
    results = []
    for size in sizes:
        nsteps = max(20, int(round(args.atom_steps / natoms(size) / 10)) * 10)
        for key in keys:
            t0 = time.time()
            results.append(run_one(key, size, nsteps, args.ranks, args.out, plugin))
            r = results[-1]
            print(f"  {key} {size} ({r['atoms']} atoms, {nsteps} steps, {args.ranks} ranks): peak RSS "
                  f"{r['rss'] / 2**20:.1f} MB, memory line {r['line'] / 2**20:.1f} MB, {time.time() - t0:.0f} s", flush=True)
    print("end:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    table(results, sizes)
    sys.exit(0 if verdicts(results) else 1)


if __name__ == "__main__":
    main()
