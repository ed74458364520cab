"""Runs the settling demo on 2 MPI ranks with the dembridge plugin and plots the result.

Usage: python run_demo.py [--plugin build/dembridgeplugin.so] [--np 2] [--out examples/settle/out] [--var NAME VALUE]...
Outputs: out/settle.dump (OVITO reads it), out/log.lammps, out/settle.png (the plots), out/snapshot.png (the beads
coloured by speed on the floor, 0.1 s after the start, while the column compacts).
"""
import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
import dembridge  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--plugin", default=dembridge.plugin_path())
    ap.add_argument("--np", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(HERE, "out"))
    ap.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"),
                    help="a deck variable (nx, ny, nz, steps): a smaller or shorter run")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    log = os.path.join(a.out, "log.lammps")
    cmd = [dembridge.mpiexec(), "-n", str(a.np), dembridge.lmp_executable(), "-in", os.path.join(HERE, "in.settle"),
           "-var", "plugin", os.path.abspath(a.plugin), "-var", "out", a.out, "-log", log]
    cmd += [w for name, value in a.var for w in ("-var", name, value)]
    print("running:", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, cwd=HERE, timeout=600)

    from dembridge import plotting

    plt = plotting.pyplot()
    th = dembridge.read_thermo(log)[-1]
    dt = 2e-5
    frames = dembridge.read_dump_atoms(os.path.join(a.out, "settle.dump"))
    step, frame = frames[-1]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    plotting.energy_history(ax1, th, dt, ["KinEng", "c_rke"], ["translational KE", "rotational KE"])
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("energy (J)")
    ax1.set_title("pair_style gran/hooke: bed settling")
    nslice = plotting.packing_slice(ax2, frame, axis="y", thickness=0.009)  # one lattice layer, mid-bed
    ax2.set_xlabel("x (m)")
    ax2.set_ylabel("z (m)")
    ax2.set_title(f"final packing, 9 mm slice ({nslice} of {len(frame['id'])} beads), colour = radius")
    png = os.path.join(a.out, "settle.png")
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    snap_step, snap = min(frames, key=lambda f: abs(f[0] * dt - 0.1))
    render_snapshot(snap, snap_step * dt, os.path.join(a.out, "snapshot.png"))
    print(f"demo done: {len(frame['id'])} beads settled in {th['Step'][-1] * dt:.2f} s simulated time")
    print(f"  dump (OVITO): {os.path.join(a.out, 'settle.dump')}")
    print(f"  log:          {log}")
    print(f"  plot:         {png}")
    print(f"  snapshot:     {os.path.join(a.out, 'snapshot.png')}")


def render_snapshot(atoms, t, png):
    """The beads coloured by speed over the floor (z = 0) at time t."""
    from dembridge import render
    x, r, v = render.spheres(atoms)
    lo, hi = (x - r[:, None]).min(axis=0), (x + r[:, None]).max(axis=0)
    render.snapshot(png, (x, r, v), [render.plane("z", 0.0, lo, hi)], elev=15, azim=-60,
                    title=f"t = {t:.2f} s: {len(r)} beads settling on the floor")


if __name__ == "__main__":
    main()
