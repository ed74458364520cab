"""Coupled main demo (issue 11): a hopper's contents held back by a hinged gate. LAMMPS (2 MPI
ranks) runs the particles and the gate's STL surface; the gate's body, hinge and spring are
MBDyn's (gate.mbd). A real `mbdyn` on PATH is used; otherwise the test peer plays the same model
(rigid body, revolute hinge, torsion spring and damper, weight; coupling/testpeer).

Usage: python run_demo.py [--plugin build/dembridgeplugin.so] [--testpeer build/coupling/mbdyn_testpeer]
                          [--np 1] [--steps 12500] [--out examples/mbdyn_gate/out]
--steps N runs N LAMMPS steps (2e-5 s each; the MBDyn side runs N/10 steps of 2e-4 s): a smaller N
gives a shorter demo (the tests run 500).
Outputs in --out: gate.txt (t, opening angle, granular moment about the hinge, particles out),
gate.png (the plots), snapshot.png (the particles coloured by speed with the gate and the walls, at the widest
opening), particles.*.dump (OVITO), gate_*.vtk (ParaView), log.lammps, mbdyn.log.
With a real MBDyn, --out also gets gate.mbd: this folder's gate.mbd with the socket path made
absolute (MBDyn changes into its input file's folder and creates a relative socket there) and the
final time of --steps; MBDyn's outputs are gate.mov, gate.out, ... Nothing is written here.
"""
import argparse
import glob
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
import dembridge  # noqa: E402
from dembridge.coupled_run import clear_stale_socket, finish_mbdyn_side  # noqa: E402

# The MBDyn model of gate.mbd, for the test peer.
HINGE = (0.002, 0.0, 0.1)
MASS, INERTIA, K, C, L = 0.5, 1.7e-3, 0.5, 0.01, 0.05
MBDYN_DT = 2e-4


LAMMPS_DT = 2e-5


def mbdyn_input(out, sock, steps):
    """gate.mbd for this run, in out: the socket at the absolute path sock and the final time of
    `steps` LAMMPS steps, so MBDyn and LAMMPS end together."""
    text = open(os.path.join(HERE, "gate.mbd")).read()
    edits = (('path, "mbdyn.sock"', f'path, "{sock}"'),
             ("final time: 0.25;", f"final time: {round(steps * LAMMPS_DT / MBDYN_DT)}*{MBDYN_DT!r};"))
    for old, new in edits:
        if text.count(old) != 1:
            sys.exit(f"run_demo: {HERE}/gate.mbd: expected one '{old}' to replace")
        text = text.replace(old, new)
    path = os.path.join(out, "gate.mbd")
    open(path, "w").write(text)
    return path


def start_mbdyn(out, sock, steps):
    mbdyn = shutil.which("mbdyn")
    if mbdyn:
        print(f"run_demo: using MBDyn at {mbdyn}")
        return subprocess.Popen([mbdyn, "-f", mbdyn_input(out, sock, steps), "-o", os.path.join(out, "gate")],
                                cwd=out, stdout=open(os.path.join(out, "mbdyn.log"), "w"), stderr=subprocess.STDOUT)
    peer = args.testpeer or dembridge.testpeer_path()  # pip's, or the source tree's build/coupling/mbdyn_testpeer
    print("run_demo: no mbdyn on PATH; the test peer plays gate.mbd")
    # 10 MBDyn steps more than LAMMPS runs: LAMMPS ends first and asks the peer to stop (status 2)
    return subprocess.Popen(testpeer_command(peer, sock, round(steps * LAMMPS_DT / MBDYN_DT) + 10, out),
                            stdout=open(os.path.join(out, "mbdyn.log"), "w"), stderr=subprocess.STDOUT)


def testpeer_command(peer, sock, mbdyn_steps, out):
    """The test peer playing gate.mbd's model for mbdyn_steps steps, listening on sock."""
    return [peer, "--path", sock, "--nodes", "1", "--orientation", "matrix", "--coupling", "loose",
            "--steps", str(mbdyn_steps), "--dt", repr(MBDYN_DT), "--mass", repr(MASS), "--inertia", repr(INERTIA),
            "--gravity", "0,0,-9.81", "--x0", ",".join(map(repr, HINGE)), "--v0", "0,0,0", "--spin0", "0,0",
            "--tilt", "0", "--spin-axis", "0,1,0", "--hinge", f"{K},{C},0,0,{-L}",
            "--trajectory", os.path.join(out, "gate_mbdyn.txt"), "--accept-timeout", "120", "--io-timeout", "300"]


def plot(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = [[float(v) for v in l.split()] for l in open(os.path.join(out, "gate.txt")) if not l.startswith("#")]
    t = [r[0] for r in rows]
    fig, ax = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    ax[0].plot(t, [r[1] for r in rows])
    ax[0].set_ylabel("gate opening [deg]")
    ax[1].plot(t, [r[2] for r in rows])
    ax[1].set_ylabel("granular moment\nabout the hinge [N m]")
    ax[2].plot(t, [r[3] for r in rows])
    ax[2].set_ylabel("particles past the gate")
    ax[2].set_xlabel("t [s]")
    fig.suptitle("Hinged gate (MBDyn side) holding back a hopper's contents (LAMMPS + dembridge)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "gate.png"), dpi=120)
    return rows


def snapshot(out, rows):
    """The dumped frame nearest the widest opening, rendered with the gate (its mesh of that step) and the
    floor, back and far side walls (the near side wall is left out so the particles show)."""
    from dembridge import render
    t_peak, angle = max(rows, key=lambda r: r[1])[:2]
    step = min((int(re.search(r"(\d+)\.dump$", f).group(1)) for f in glob.glob(os.path.join(out, "particles.*.dump"))),
               key=lambda s: abs(s * LAMMPS_DT - t_peak))
    atoms = dembridge.read_dump_atoms(os.path.join(out, f"particles.{step}.dump"))[0][1]
    lo, hi = (-0.1, -0.04, 0.0), (0.2, 0.04, 0.1)
    walls = [render.plane("z", 0.0, lo, hi), render.plane("x", -0.1, lo, hi), render.plane("y", 0.04, lo, hi)]
    gate = render.read_vtk_mesh(os.path.join(out, f"gate_{step}.vtk"))
    render.snapshot(os.path.join(out, "snapshot.png"), render.spheres(atoms), walls + [gate], elev=18, azim=-65,
                    title=f"t = {step * LAMMPS_DT:.3f} s: the gate opened by {angle:.0f}° ({len(atoms['id'])} particles)")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--plugin", default=dembridge.plugin_path())
    ap.add_argument("--testpeer", default=None)
    ap.add_argument("--np", type=int, default=1)  # 2 cores: one LAMMPS rank, one for MBDyn (or the test peer)
    ap.add_argument("--steps", type=int, default=12500)
    ap.add_argument("--out", default=os.path.join(HERE, "out"))
    args = ap.parse_args()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    sock = os.path.join(out, "mbdyn.sock")
    clear_stale_socket(sock, "run_demo")
    shutil.copy(os.path.join(HERE, "gate.stl"), os.path.join(out, "gate.stl"))
    mb = start_mbdyn(out, sock, args.steps)
    cmd = [dembridge.lmp_executable(), "-in", os.path.join(HERE, "in.gate"), "-var", "plugin", os.path.abspath(args.plugin),
           "-var", "sock", sock, "-var", "steps", str(args.steps), "-var", "out", out, "-log",
           os.path.join(out, "log.lammps"), "-nocite"]
    if args.np > 1:
        cmd = [dembridge.mpiexec(), "-n", str(args.np)] + cmd
    lmp = subprocess.run(cmd, cwd=out, stdin=subprocess.DEVNULL)
    finish_mbdyn_side(mb)
    if lmp.returncode != 0:
        sys.exit(f"run_demo: LAMMPS failed (status {lmp.returncode}); see {out}/log.lammps and {out}/mbdyn.log")
    # MBDyn: 0 when it reached its final time, 2 when LAMMPS ended first and asked it to stop.
    if mb.returncode not in (0, 2):
        sys.exit(f"run_demo: the MBDyn side failed (status {mb.returncode}); see {out}/mbdyn.log")
    rows = plot(out)
    snapshot(out, rows)
    peak = max(rows, key=lambda r: r[1])
    print(f"run_demo: gate opened up to {peak[1]:.1f} deg at t = {peak[0]:.3f} s; {int(rows[-1][3])} particles "
          f"passed it; plots in {out}/gate.png, snapshot {out}/snapshot.png, dumps in {out}/")
