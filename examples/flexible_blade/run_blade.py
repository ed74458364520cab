"""examples/flexible_blade: a cantilevered flexible blade (MBDyn's modal joint, blade.mbd) under a
batch of falling particles (LAMMPS, in.blade), coupled through MBDyn's `external modal`. A real
`mbdyn` on PATH is not used: the test peer (coupling/testpeer, `--modal-*`) integrates the blade's
modal equations M q'' + C q' + K q = p with blade.fem's modal mass, stiffness and damping.

Usage: python run_blade.py [--plugin build/dembridgeplugin.so] [--testpeer build/coupling/mbdyn_testpeer]
                           [--steps 15000] [--every 500] [--out examples/flexible_blade/out] [--no-plot]
                           [--surface atoms|mesh]
Outputs in --out: modes.txt (the test peer's t, q1 q2, q1' q2', q1'' q2'', p1 p2 per step),
blade.png (tip deflection and generalized forces over time), snapshot.png (the particles coloured by speed on
the bent blade, at its largest deflection), blade.*.dump (the particles and the
blade atoms, OVITO), log.lammps, mbdyn.log; with --surface mesh (the blade's surface the STL mesh
blade.stl instead of a wall of atoms) also surface_*.vtk (ParaView) and surface_*.stl, the deformed mesh."""
import argparse
import glob
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
import dembridge  # noqa: E402
import numpy as np  # noqa: E402
from dembridge.coupled_run import clear_stale_socket, finish_mbdyn_side  # noqa: E402

DT = 2e-5  # MBDyn's time step = LAMMPS's timestep (external modal: one exchange per LAMMPS step)


def read_fem(path):
    """The record groups of an MBDyn FEM file this example needs: node labels (2), coordinates
    (5-7), the translations of the mode shapes (8) and the diagonals of the modal mass (9),
    stiffness (10) and damping (13) matrices."""
    groups, g = {}, None
    for line in open(path):
        if line.startswith("** RECORD GROUP"):
            g = int(line.split()[3].rstrip(","))
            groups[g] = []
        elif not line.startswith("**") and g is not None:
            groups[g] += line.split()
    n = int(groups[1][1])
    modes = int(groups[1][2]) + int(groups[1][3]) + int(groups[1][4]) - int(groups[1][5])
    xyz = [tuple(float(groups[c][i]) for c in (5, 6, 7)) for i in range(n)]
    shape = [float(v) for v in groups[8]]
    phi = [[tuple(shape[(m * n + i) * 6 + k] for k in range(3)) for i in range(n)] for m in range(modes)]
    diag = {g: [float(groups[g][m * modes + m]) for m in range(modes)] for g in (9, 10, 13)}
    return {"labels": groups[2], "xyz": xyz, "phi": phi, "mass": diag[9], "stiffness": diag[10], "damping": diag[13]}


def testpeer_command(peer, sock, fem, steps, out):
    """The test peer playing blade.mbd: MBDyn's modal joint on a clamped node, external modal type modal."""
    lst = lambda v: ",".join(map(repr, v))  # noqa: E731
    return [peer, "--path", sock, "--steps", str(steps), "--dt", repr(DT), "--modal-mass", lst(fem["mass"]),
            "--modal-stiffness", lst(fem["stiffness"]), "--modal-damping", lst(fem["damping"]),
            "--trajectory", os.path.join(out, "modes.txt"), "--accept-timeout", "60", "--io-timeout", "120"]


def read_modes(out):
    """Rows of modes.txt: t, q1 q2, q1' q2', q1'' q2'', p1 p2."""
    return [[float(v) for v in l.split()] for l in open(os.path.join(out, "modes.txt")) if not l.startswith("#")]


def run(plugin, peer, steps, every, out, surface="atoms"):
    out = os.path.abspath(out)
    os.makedirs(out, exist_ok=True)
    sock = os.path.join(out, "mbdyn.sock")
    clear_stale_socket(sock, "run_blade")
    fem_path = os.path.join(HERE, "blade.fem")
    mb = subprocess.Popen(testpeer_command(peer, sock, read_fem(fem_path), steps, out),
                          stdout=open(os.path.join(out, "mbdyn.log"), "w"), stderr=subprocess.STDOUT)
    cmd = [dembridge.lmp_executable(), "-in", os.path.join(HERE, "in.blade"), "-var", "plugin", os.path.abspath(plugin),
           "-var", "sock", sock, "-var", "steps", str(steps), "-var", "every", str(every), "-var", "out", out,
           "-var", "fem", fem_path, "-var", "stl", os.path.join(HERE, "blade.stl"), "-var", "surface", surface, "-log", os.path.join(out, "log.lammps"), "-nocite", "-screen", "none"]
    lmp = subprocess.run(cmd, cwd=out, stdin=subprocess.DEVNULL)
    status = finish_mbdyn_side(mb)
    if lmp.returncode != 0:
        sys.exit(f"run_blade: LAMMPS failed (status {lmp.returncode}); see {out}/log.lammps and {out}/mbdyn.log")
    if status != 0:  # both run `steps` steps: the peer completes (0)
        sys.exit(f"run_blade: the MBDyn side failed (status {status}); see {out}/mbdyn.log")
    return out


def plot(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = read_modes(out)
    t = [r[0] for r in rows]
    fig, ax = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    # tip deflection: mode 1 is 1 at the tip, mode 2 is +-1 at the tip's edges (0 at mid-width)
    ax[0].plot(t, [1e3 * r[1] for r in rows], label="mid-width (q1)")
    ax[0].plot(t, [1e3 * (r[1] + r[2]) for r in rows], label="edge y = +W/2 (q1 + q2)", lw=0.8)
    ax[0].set_ylabel("tip deflection z [mm]")
    ax[0].legend(fontsize=8)
    ax[1].plot(t, [r[7] for r in rows], label="p1 (bending)")
    ax[1].plot(t, [r[8] for r in rows], label="p2 (torsion)", lw=0.8)
    ax[1].set_ylabel("generalized force [N]")
    ax[1].set_xlabel("t [s]")
    ax[1].legend(fontsize=8)
    fig.suptitle("Cantilevered blade (MBDyn modal joint) under falling particles (LAMMPS + dembridge)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "blade.png"), dpi=120)


def snapshot(out, surface):
    """The dumped frame nearest the largest tip deflection, rendered: the falling spheres coloured by speed,
    with the blade's surface (blade.stl with its vertices at the blade atoms, or the deformed mesh of that step with
    --surface mesh)."""
    from dembridge import render
    t_low = min(read_modes(out), key=lambda r: r[1])[0]
    steps = [int(re.search(r"(\d+)\.dump$", f).group(1)) for f in glob.glob(os.path.join(out, "blade.*.dump"))]
    step = min(steps, key=lambda s: abs(s * DT - t_low))
    atoms = dembridge.read_dump_atoms(os.path.join(out, f"blade.{step}.dump"))[0][1]
    balls = render.spheres(atoms, atoms["type"] == 1)
    if surface == "mesh":
        blade = render.read_vtk_mesh(os.path.join(out, f"surface_{step}.vtk"))
    else:  # blade.stl's triangles with each vertex at its blade atom (the one nearest it in the x-y plane)
        blade = render.read_stl(os.path.join(HERE, "blade.stl"))
        mine = atoms["type"] == 2
        xyz = np.column_stack([atoms["x"][mine], atoms["y"][mine], atoms["z"][mine]])
        flat = blade.reshape(-1, 3)
        nearest = np.argmin(((flat[:, None, :2] - xyz[None, :, :2]) ** 2).sum(axis=2), axis=1)
        blade = xyz[nearest].reshape(blade.shape)
    meshes = [blade]
    render.snapshot(os.path.join(out, "snapshot.png"), balls, meshes, elev=25, azim=-55,
                    title=f"t = {step * DT:.3f} s: the blade bent down by the particles")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--plugin", default=dembridge.plugin_path())
    ap.add_argument("--testpeer", default=dembridge.testpeer_path())  # pip's, or the source tree's build
    ap.add_argument("--steps", type=int, default=15000)
    ap.add_argument("--every", type=int, default=500)
    ap.add_argument("--out", default=os.path.join(HERE, "out"))
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--surface", choices=("atoms", "mesh"), default="atoms")
    a = ap.parse_args()
    out = run(a.plugin, a.testpeer, a.steps, a.every, a.out, a.surface)
    if not a.no_plot:
        plot(out)
        snapshot(out, a.surface)
    rows = read_modes(out)
    low = min(rows, key=lambda r: r[1])
    print(f"run_blade: tip deflected down to {1e3 * low[1]:.2f} mm at t = {low[0]:.4f} s, "
          f"{1e3 * rows[-1][1]:.2f} mm at the end; outputs in {out}/")
