#!/usr/bin/env python3
"""The instruction targets of the chute and the STL hopper, each as a ratio against its reference measured in the
same invocation (bench/README.md, "Targets"):

  P2  LAMMPS numeric syntax vs the LAMMPS built-in (plg_hooke / lmp_hooke, plg_hertz / lmp_hertz):
      Ir per atom-step <= 0.85, loop wall time (1 rank) <= 0.75
  P1  LIGGGHTS 2.x syntax vs LIGGGHTS 3.8 (plg_hertz2x / lig_hertzmat, plg_hooke2xstiff / lig_hooke): Ir <= 0.55
  P6  STL hopper vs LIGGGHTS 3.8: Ir per atom-step <= 0.60; the mesh wall part <= 0.5

It runs run_chute_bench.py (the eight configurations) and run_hopper_bench.py into --out, reads their CSV files
and prints one line per target with the figures, the ratio and the verdict, and `uptime` before and after (wall
times depend on the load; instruction counts do not). Instructions: callgrind of the MD loop only
(LAMMPS_NS::Verlet::run, the same symbol in LIGGGHTS 3.8), serial.

usage: .venv/bin/python bench/run_targets_bench.py [--steps 200] [--hopper-steps 100] [--wall-steps 1000]
           [--hopper-wall-steps 300] [--rounds 3] [--no-wall] [--references DIR] [--out bench/out/targets]
About 25 min on an idle 2-core machine with the defaults; --steps 50 --hopper-steps 40 --no-wall about 6 min.

--references DIR: the instruction counts of the references (the LAMMPS built-ins, LIGGGHTS 3.8 on the chute and
the hopper) are read from an earlier invocation's --out DIR with the same step counts instead of measured again
(callgrind counts of the same binaries and decks repeat exactly: the built-in's 660.5 Ir/atom-step at 200 steps is
the baseline's to the instruction); only the plugin runs under callgrind. The wall times are measured here in
any case, the P2 ones (built-in and plugin, 1 rank) interleaved in this invocation.
"""
import argparse
import csv
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
PY = os.path.join(REPO, ".venv", "bin", "python")
CHUTE_KEYS = ["lmp_hooke", "plg_hooke", "lmp_hertz", "plg_hertz", "lig_hertzmat", "plg_hertz2x", "lig_hooke", "plg_hooke2xstiff"]
# (target, measured key, reference key, what, limit)
CHUTE_TARGETS = [("P2", "plg_hooke", "lmp_hooke", "ir", 0.85), ("P2", "plg_hooke", "lmp_hooke", "wall", 0.75),
                 ("P2", "plg_hertz", "lmp_hertz", "ir", 0.85), ("P2", "plg_hertz", "lmp_hertz", "wall", 0.75),
                 ("P1", "plg_hertz2x", "lig_hertzmat", "ir", 0.55), ("P1", "plg_hooke2xstiff", "lig_hooke", "ir", 0.55)]


def uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def verdict(value, limit):
    return "n/a" if value != value else ("met" if value <= limit else "NOT met")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=200, help="chute callgrind steps")
    ap.add_argument("--hopper-steps", type=int, default=100, help="hopper callgrind steps")
    ap.add_argument("--wall-steps", type=int, default=1000, help="chute wall-time steps")
    ap.add_argument("--hopper-wall-steps", type=int, default=300)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--no-wall", action="store_true")
    ap.add_argument("--plugin", default=os.path.join(REPO, "build", "dembridgeplugin.so"))
    ap.add_argument("--out", default=os.path.join(HERE, "out", "targets"))
    ap.add_argument("--references", default="", help="an earlier --out folder whose reference instruction counts are reused")
    a = ap.parse_args()
    chute_out, hopper_out = os.path.join(a.out, "chute"), os.path.join(a.out, "hopper")
    os.makedirs(hopper_out, exist_ok=True)
    start = uptime()
    wall = ["--no-wall"] if a.no_wall else []
    chute = [PY, os.path.join(HERE, "run_chute_bench.py"), "--steps", str(a.steps), "--wall-steps", str(a.wall_steps), "--rounds",
             str(a.rounds), "--plugin", a.plugin]
    hopper = [PY, os.path.join(HERE, "run_hopper_bench.py"), "--steps", str(a.hopper_steps), "--wall-steps", str(a.hopper_wall_steps),
              "--rounds", str(a.rounds), "--plugin", a.plugin, "--out", hopper_out]
    if not a.references:
        subprocess.run(chute + ["--only", ",".join(CHUTE_KEYS), "--out", chute_out, *wall], check=False)
        subprocess.run(hopper + wall, check=True)
    else:
        plugin_keys = [k for k in CHUTE_KEYS if k.startswith("plg_")]
        wall_keys = sorted({k for t in CHUTE_TARGETS if t[3] == "wall" for k in t[1:3]})
        subprocess.run(chute + ["--only", ",".join(plugin_keys), "--out", chute_out, "--no-wall"], check=False)
        if not a.no_wall:
            subprocess.run(chute + ["--only", ",".join(wall_keys), "--out", chute_out + "_wall", "--no-callgrind", "--wall-ranks", "1"],
                           check=False)
        subprocess.run(hopper + ["--codes", "lammps", "--no-wall"], check=True)
    end = uptime()
    rows = {r["key"]: r for r in csv.DictReader(open(os.path.join(chute_out, "results.csv")))}
    hop = {r["code"]: r for r in csv.DictReader(open(os.path.join(hopper_out, "hopper_results.csv")))}
    if a.references:  # reference instruction counts from the earlier run, wall times from this one
        ref_rows = {r["key"]: r for r in csv.DictReader(open(os.path.join(a.references, "chute", "results.csv")))}
        ref_hop = {r["code"]: r for r in csv.DictReader(open(os.path.join(a.references, "hopper", "hopper_results.csv")))}
        for k, r in ref_rows.items():
            if int(r["cg_steps"]) != a.steps:
                sys.exit(f"run_targets_bench: --references {a.references}: chute callgrind of {r['cg_steps']} steps, not {a.steps}")
            if not k.startswith("plg_"):
                rows[k] = dict(r, best1="nan")
        if int(ref_hop["liggghts"]["steps"]) != a.hopper_steps:
            sys.exit(f"run_targets_bench: --references {a.references}: hopper callgrind of {ref_hop['liggghts']['steps']} steps")
        hop["liggghts"] = ref_hop["liggghts"]
        hop["lammps"]["loop_best"] = "nan"
        if not a.no_wall:
            for k, r in ((r["key"], r) for r in csv.DictReader(open(os.path.join(chute_out + "_wall", "results.csv")))):
                rows[k]["best1"] = r["best1"]
    refs = (f"; reference instruction counts read from {a.references} (same binaries, decks and step counts)"
            if a.references else "")
    lines = ["", f"Targets (ratios against the reference of the same invocation{refs}; chute callgrind {a.steps} steps, "
             f"hopper {a.hopper_steps} steps, wall time best of {a.rounds} rounds):", "",
             "| target | measured | reference | figure | measured | reference | ratio | limit | verdict |", "|---|---|---|---|---|---|---|---|---|"]
    for target, key, ref, what, limit in CHUTE_TARGETS:
        col, unit = ("ir_per_atom_step", "Ir/atom-step") if what == "ir" else ("best1", "loop s, 1 rank")
        m, r = float(rows[key][col]), float(rows[ref][col])
        lines.append(f"| {target} | {key} | {ref} | {unit} | {m:.1f} | {r:.1f} | {m / r:.3f} | {limit} | {verdict(m / r, limit)} |"
                     if what == "ir" else
                     f"| {target} | {key} | {ref} | {unit} | {m:.2f} | {r:.2f} | {m / r:.3f} | {limit} | {verdict(m / r, limit)} |")
    for what, col, limit in (("Ir/atom-step", "ir_per_atom_step", 0.60), ("mesh wall part Ir/atom-step", "wall_part_ir_per_atom_step", 0.5),
                             ("hopper loop s, 1 rank", "loop_best", None)):
        m, r = float(hop["lammps"][col]), float(hop["liggghts"][col])
        lines.append(f"| P6 | hopper (plugin) | LIGGGHTS 3.8 | {what} | {m:.2f} | {r:.2f} | {m / r:.3f} | {limit or '-'} | "
                     f"{verdict(m / r, limit) if limit else '(reported)'} |")
    lines += ["", f"uptime at start: `{start}`", f"uptime at end: `{end}`"]
    text = "\n".join(lines)
    print(text)
    open(os.path.join(a.out, "targets.md"), "w").write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
