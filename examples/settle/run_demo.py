"""Runs the settling demo on 2 MPI ranks with the dembridge plugin and plots the result.

Usage: python run_demo.py [--plugin build/dembridgeplugin.so] [--np 2] [--out examples/settle/out]
Outputs: out/settle.dump (OVITO reads it), out/log.lammps, out/settle.png.
"""
import argparse
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
import dembridge  # noqa: E402


def read_thermo(log):
    rows, cols = [], None
    for line in open(log):
        w = line.split()
        if w[:1] == ["Step"]:
            cols = w
            continue
        if cols and len(w) == len(cols) and re.match(r"^\d+$", w[0]):
            rows.append([float(x) for x in w])
        elif cols and w[:1] == ["Loop"]:
            cols = None
    return rows


def last_frame(dump):
    """(radius, x, y, z) of the last frame of a dump custom file."""
    frame, cols = None, None
    with open(dump) as fh:
        lines = fh.read().splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: NUMBER OF ATOMS"):
            n = int(lines[i + 1])
        if lines[i].startswith("ITEM: ATOMS"):
            cols = lines[i].split()[2:]
            frame = [l.split() for l in lines[i + 1:i + 1 + n]]
            i += n
        i += 1
    idx = {c: k for k, c in enumerate(cols)}
    return [(float(r[idx["radius"]]), float(r[idx["x"]]), float(r[idx["y"]]), float(r[idx["z"]])) for r in frame]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--plugin", default=dembridge.plugin_path())
    ap.add_argument("--np", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(HERE, "out"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    log = os.path.join(a.out, "log.lammps")
    cmd = [dembridge.mpiexec(), "-n", str(a.np), dembridge.lmp_executable(), "-in", os.path.join(HERE, "in.settle"),
           "-var", "plugin", os.path.abspath(a.plugin), "-var", "out", a.out, "-log", log, "-screen", "none"]
    print("running:", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, cwd=HERE, timeout=600)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    th = read_thermo(log)
    dt = 2e-5
    parts = last_frame(os.path.join(a.out, "settle.dump"))
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    ax1.semilogy([r[0] * dt for r in th], [max(r[2], 1e-30) for r in th], label="translational KE")
    ax1.semilogy([r[0] * dt for r in th], [max(r[3], 1e-30) for r in th], label="rotational KE")
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("energy (J)")
    ax1.set_title("pair_style gran/hooke: bed settling")
    ax1.legend()
    ymid = 0.5 * (min(p[2] for p in parts) + max(p[2] for p in parts))
    cmap = plt.get_cmap("viridis")
    for rad, x, y, z in parts:
        if abs(y - ymid) < 0.0045:  # one lattice layer thick slice through the middle
            ax2.add_patch(plt.Circle((x, z), rad, color=cmap((rad - 0.0015) / 0.0005), alpha=0.8))
    ax2.set_xlim(0, max(p[1] for p in parts) + 0.003)
    ax2.set_ylim(0, max(p[3] for p in parts) + 0.003)
    ax2.set_aspect("equal")
    ax2.set_xlabel("x (m)")
    ax2.set_ylabel("z (m)")
    ax2.set_title(f"final packing, 9 mm slice, colour = radius ({len(parts)} beads)")
    png = os.path.join(a.out, "settle.png")
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(f"demo done: {len(parts)} beads settled in {th[-1][0] * dt:.2f} s simulated time")
    print(f"  dump (OVITO): {os.path.join(a.out, 'settle.dump')}")
    print(f"  log:          {log}")
    print(f"  plot:         {png}")


if __name__ == "__main__":
    main()
