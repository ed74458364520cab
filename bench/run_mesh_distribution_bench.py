#!/usr/bin/env python3
"""Distributed mesh benchmark: a flat plate of about 10^6 triangles (write_plate: n x n squares, two
triangles each, binary STL) under a layer of spheres that falls onto it, pairs + one mesh wall, hertz +
tangential history. Runs the same deck with the mesh replicated ('distribute no') on 1 and 4 ranks and
distributed ('distribute yes', the default) on 4 ranks, and prints for each:
  * the mesh memory per rank (fix mesh/surface's own figure after the setup: triangles, geometry,
    topology, bins, candidate lists, force buffers), min and max over the ranks;
  * the peak RSS of each rank (/usr/bin/time; the whole mesh is read on every rank before it is split,
    so the peak includes it once);
  * LAMMPS's "Per MPI rank memory allocation" (max; it includes the mesh fix's figure);
  * the MD loop time ('Loop time') and the whole run's time (reading and splitting the mesh included).
The target ratio is max mesh bytes per rank on 4 ranks distributed / mesh bytes on 1 rank.
Checks that the final atoms (positions, velocities) are the same bit for bit in all three runs.

usage: /work/main/.venv/bin/python bench/run_mesh_distribution_bench.py [--n 707] [--steps 200] [--out DIR]
"""
import argparse
import os
import re
import shutil
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from run_hopper_bench import VENV, env_of, raw_lmp  # noqa: E402

DECK = """plugin load {plugin}
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
region box block -0.5 0.5 -0.5 0.5 -0.02 0.1 units box
create_box 1 box
lattice sc 0.01 origin 0.5 0.5 0.25
region layer block -0.48 0.48 -0.48 0.48 0.001 0.006 units box
create_atoms 1 region layer
set group all diameter 0.004 density 2500
velocity all set 0.0 0.0 -1.0 units box
neighbor 0.001 bin
neigh_modify delay 0
timestep 1e-5
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style gran model hertz tangential history
pair_coeff * *
fix plate all mesh/surface/stress file plate.stl type 1 distribute {dist}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes plate
fix integr all nve/sphere
fix grav all gravity 9.81 vector 0 0 -1
thermo_style custom step atoms ke f_plate[3]
thermo_modify norm no format float %.17g
thermo {steps}
run {steps}
write_dump all custom final.{tag} id x y z vx vy vz modify sort id format float %.17g
"""


def write_plate(path, n, half=0.5):
    """n x n squares over [-half, half]^2 at z = 0, two triangles each (2 n^2 triangles), binary STL"""
    h = 2.0 * half / n
    with open(path, "wb") as f:
        f.write(b"dembridge bench plate".ljust(80, b" "))
        f.write(struct.pack("<I", 2 * n * n))
        rec = struct.Struct("<12fH")
        for i in range(n):
            x0, x1 = -half + i * h, -half + (i + 1) * h
            for j in range(n):
                y0, y1 = -half + j * h, -half + (j + 1) * h
                f.write(rec.pack(0, 0, 1, x0, y0, 0, x1, y0, 0, x1, y1, 0, 0))
                f.write(rec.pack(0, 0, 1, x0, y0, 0, x1, y1, 0, x0, y1, 0, 0))


def run(out, nprocs, dist, steps, plugin):
    tag = f"{dist}.np{nprocs}"
    open(os.path.join(out, f"in.{tag}"), "w").write(DECK.format(plugin=plugin, dist=dist, steps=steps, tag=tag))
    lmp = [raw_lmp(), "-in", f"in.{tag}", "-log", f"log.{tag}", "-nocite", "-screen", "none"]
    timed = ["/usr/bin/time", "-f", "RSS_KB %M", "-a", "-o", f"rss.{tag}"] + lmp
    cmd = timed if nprocs == 1 else [os.path.join(VENV, "bin", "mpiexec"), "-n", str(nprocs)] + timed
    if os.path.exists(os.path.join(out, f"rss.{tag}")):
        os.remove(os.path.join(out, f"rss.{tag}"))
    t0 = time.time()
    subprocess.run(cmd, cwd=out, env=env_of("lammps"), check=True)
    elapsed = time.time() - t0
    text = open(os.path.join(out, f"log.{tag}")).read()
    m = re.search(r"\(id plate\): (all|part) of (\d+) triangles per rank \((\d+) to (\d+)\), mesh memory ([0-9.]+) to ([0-9.]+) kB",
                  text)
    loop = float(re.search(r"^Loop time of ([0-9.eE+-]+)", text, re.M).group(1))
    natoms = int(re.search(r"Created (\d+) atoms", text).group(1))
    lammps_mb = float(re.search(r"Per MPI rank memory allocation \(min/avg/max\) = \S+ \| \S+ \| (\S+) Mbytes", text).group(1))
    rss = [int(v) for v in re.findall(r"RSS_KB (\d+)", open(os.path.join(out, f"rss.{tag}")).read())]
    return {"tag": tag, "kind": m.group(1), "ntri": int(m.group(2)), "tri_lo": int(m.group(3)), "tri_hi": int(m.group(4)),
            "kb_lo": float(m.group(5)), "kb_hi": float(m.group(6)), "loop": loop, "elapsed": elapsed, "rss": rss,
            "natoms": natoms, "lammps_mb": lammps_mb, "final": final_atoms(os.path.join(out, f"final.{tag}"))}


def final_atoms(path):
    """the atoms' x and v as text, without ids (create_atoms numbers them by rank), sorted"""
    rows = open(path).read().split("ITEM: ATOMS")[1].splitlines()[1:]
    return sorted(r.split(None, 1)[1] for r in rows if r.strip())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=707, help="squares per side (2 n^2 triangles; 707 -> 999 698)")
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--plugin", default=os.path.join(REPO, "build", "dembridgeplugin.so"))
    ap.add_argument("--out", default=os.path.join(HERE, "out", "mesh_distribution"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    plugin = os.path.join(a.out, "dembridgeplugin.so")
    shutil.copy(a.plugin, plugin)  # a rebuild during the run does not change what is measured
    write_plate(os.path.join(a.out, "plate.stl"), a.n)
    res = [run(a.out, n, d, a.steps, plugin) for n, d in ((1, "no"), (4, "no"), (4, "yes"))]
    print(f"plate of {res[0]['ntri']} triangles, {res[0]['natoms']} spheres, {a.steps} steps; load: {os.getloadavg()[0]:.1f}")
    print(f"{'run':10s} {'kept':>5s} {'triangles/rank':>17s} {'mesh kB/rank (min-max)':>24s} {'peak RSS MB/rank':>18s} "
          f"{'LAMMPS MB/rank':>15s} {'loop s':>8s} {'total s':>8s}")
    for r in res:
        rss = "-".join(f"{v / 1024:.0f}" for v in (min(r["rss"]), max(r["rss"])))
        print(f"{r['tag']:10s} {r['kind']:>5s} {r['tri_lo']:>8d}-{r['tri_hi']:<8d} {r['kb_lo']:>11.0f}-{r['kb_hi']:<12.0f} "
              f"{rss:>18s} {r['lammps_mb']:15.1f} {r['loop']:8.2f} {r['elapsed']:8.2f}")
    ratio = res[2]["kb_hi"] / res[0]["kb_hi"]
    same = res[0]["final"] == res[1]["final"] == res[2]["final"]
    print(f"mesh memory per rank, 4 ranks distributed / 1 rank: {ratio:.3f} (target <= 0.35)")
    print(f"final atoms identical in the three runs: {same}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
