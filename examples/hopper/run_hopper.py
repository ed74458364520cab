"""Hopper discharge onto a conveyor belt: writes the meshes, runs in.hopper with the dembridge
plugin (the venv's lmp, optionally under mpiexec) and plots the mass flow rate out of the funnel
and the force on the funnel.

Usage: python run_hopper.py [--np 2] [--settle 15000] [--run 40000] [--out examples/hopper/out]
Outputs: out/log.lammps, out/hopper.dump and out/mesh_*.vtk (ParaView/OVITO), out/hopper.png (the plots),
out/snapshot.png (the particles coloured by speed in the funnel and on the belt, 0.2 s after the outlet opens).
"""
import argparse
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
import dembridge  # noqa: E402
import write_geometry  # noqa: E402

MASS = 2500 * 4.0 / 3.0 * 3.141592653589793 * 0.0015 ** 3  # one particle (d = 3 mm, 2500 kg/m3)


def read_thermo(log):
    """The thermo rows of every run of the log, in order, as dicts column -> value (dembridge.read_thermo)."""
    return [dict(zip(run, values)) for run in dembridge.read_thermo(log) for values in zip(*run.values())]


def run(out, nprocs, nsettle, nrun, quiet=False):
    os.makedirs(out, exist_ok=True)
    write_geometry.write_binary(os.path.join(out, "funnel.stl"), write_geometry.funnel())
    write_geometry.write_ascii(os.path.join(out, "belt.stl"), write_geometry.belt(), "belt")
    shutil.copy(os.path.join(HERE, "in.hopper"), os.path.join(out, "in.hopper"))
    cmd = [dembridge.lmp_executable(), "-in", "in.hopper", "-log", "log.lammps", "-nocite",
           "-var", "NSETTLE", str(nsettle), "-var", "NRUN", str(nrun), "-var", "OUT", "."]
    deck = open(os.path.join(out, "in.hopper")).read()
    open(os.path.join(out, "in.hopper"), "w").write(f"plugin load {dembridge.plugin_path()}\n" + deck)
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    subprocess.run(cmd, cwd=out, check=True, stdout=subprocess.DEVNULL if quiet else None)  # thermo = progress
    return read_thermo(os.path.join(out, "log.lammps"))


def flow_rate(rows, nsettle, span=10):
    """(time, kg/s) from the particles left in the funnel: differences over `span` thermo rows
    (0.02 s with thermo 200, dt 1e-5), over the discharge"""
    d = [r for r in rows if r["Step"] >= nsettle]
    out = []
    for a, b in zip(d[:-span], d[span:]):
        out.append((0.5 * (a["Time"] + b["Time"]), -(b["v_nin"] - a["v_nin"]) * MASS / (b["Time"] - a["Time"])))
    return out


def summary(rows, nsettle):
    """One line: particles, how many are left in the funnel, the peak flow rate (if the run was long enough)."""
    fr = flow_rate(rows, nsettle)
    peak = f"peak flow rate {max(b for _, b in fr) * 1e3:.2f} g/s" if fr else "run too short for a flow rate"
    return f"particles: {int(rows[0]['Atoms'])}, left in the funnel: {int(rows[-1]['v_nin'])}, {peak}"


def plot(rows, nsettle, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = [r["Time"] for r in rows]
    t_open = next((r["Time"] for r in rows if r["Step"] >= nsettle), t[-1])
    fig, ax = plt.subplots(3, 1, figsize=(7, 9), sharex=True)
    ax[0].plot(t, [r["v_nin"] * MASS * 1e3 for r in rows])
    ax[0].set_ylabel("mass in funnel [g]")
    fr = flow_rate(rows, nsettle)
    ax[1].plot([a for a, _ in fr], [b * 1e3 for _, b in fr])
    ax[1].set_ylabel("mass flow rate [g/s]")
    ax[2].plot(t, [-r["v_fz"] for r in rows], label="−F_z on funnel (fix mesh/surface/stress)")
    ax[2].plot(t, [r["v_nin"] * MASS * 9.81 for r in rows], "--", label="weight of the particles in it")
    ax[2].set_ylabel("force [N]")
    ax[2].set_xlabel("time [s]")
    ax[2].legend()
    for a in ax:
        a.axvline(t_open, color="grey", lw=0.8)
    ax[0].set_title("STL funnel discharging onto a conveyor (outlet opened at the grey line)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def snapshot(out, nsettle, png):
    """The dumped frame nearest 0.2 s after the outlet opened (the last one of a shorter run), rendered with
    the funnel and the belt."""
    from dembridge import render
    frames = dembridge.read_dump_atoms(os.path.join(out, "hopper.dump"))
    step, atoms = min(frames, key=lambda f: abs(f[0] - (nsettle + 20000)))
    meshes = [render.read_stl(os.path.join(out, name)) for name in ("funnel.stl", "belt.stl")]
    t = (step - nsettle) * 1e-5
    render.snapshot(png, render.spheres(atoms), meshes, elev=22, azim=-70,
                    title=f"{'outlet opened %.2f s ago' % t if t >= 0 else 'settling'}: {len(atoms['id'])} particles")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--settle", type=int, default=15000)
    ap.add_argument("--run", type=int, default=40000)
    ap.add_argument("--out", default=os.path.join(HERE, "out"))
    a = ap.parse_args()
    rows = run(os.path.abspath(a.out), a.np, a.settle, a.run)
    plot(rows, a.settle, os.path.join(a.out, "hopper.png"))
    snapshot(a.out, a.settle, os.path.join(a.out, "snapshot.png"))
    print(f"{summary(rows, a.settle)}; plot: {os.path.join(a.out, 'hopper.png')}, snapshot: "
          f"{os.path.join(a.out, 'snapshot.png')}")


if __name__ == "__main__":
    main()
