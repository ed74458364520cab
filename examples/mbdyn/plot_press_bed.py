"""Case a: the plate's height (MBDyn's node) and the bed's vertical load on it (sent by fix mbdyn)
against the plate's weight; and press_bed_snapshot.png beside OUT.png: the frame of press_bed.dump (in the current
folder) 0.02 s after the plate's first contact with the bed, the particles coloured by speed with the walls.
usage: python plot_press_bed.py MBDYN_TRAJ LAMMPS_PRINT OUT.png"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from dembridge import read_dump_atoms, render  # noqa: E402

mb = [[float(v) for v in l.split()] for l in open(sys.argv[1]) if l.strip() and not l.startswith("#")]
lm = [[float(v) for v in l.split()] for l in open(sys.argv[2]) if l.strip() and not l.startswith("#")]
t0 = lm[0][0]
W = 0.5 * 9.81
fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
ax1.plot([r[0] for r in mb], [r[3] for r in mb], label="MBDyn node z")
ax1.plot([r[0] - t0 for r in lm], [r[1] for r in lm], "--", label="LAMMPS plate centroid z")
ax1.set_ylabel("z [m]")
ax1.legend()
ax2.plot([r[0] - t0 for r in lm], [r[2] for r in lm], label="Fz sent to MBDyn (bed on plate)")
ax2.axhline(W, color="k", lw=0.8, ls=":", label="plate weight m g")
ax2.set_ylabel("Fz [N]")
ax2.set_xlabel("t since coupling [s]")
ax2.legend()
fig.suptitle("plate driven by MBDyn pressing into a particle bed (fix mbdyn)")
fig.tight_layout()
fig.savefig(sys.argv[3], dpi=100)
late = [r[2] for r in lm if r[0] - t0 > 0.15]
if late:
    print(f"mean Fz over the last 0.05 s: {sum(late) / len(late):.3f} N (weight {W:.3f} N); "
          f"final z: MBDyn {mb[-1][3]:.5f} m")

# the snapshot: 0.02 s after the bed first pushes on the plate (the last frame of a run without contact)
t_hit = next((r[0] for r in lm if r[2] > 0.05 * W), None)
frames = read_dump_atoms("press_bed.dump")
step, atoms = (min(frames, key=lambda f: abs(f[0] * 1e-5 - (t_hit + 0.02))) if t_hit is not None else frames[-1])
lo, hi = (-0.06, -0.06, 0.0), (0.06, 0.06, 0.1)
walls = [render.plane("z", 0.0, lo, hi), render.plane("x", -0.06, lo, hi), render.plane("y", 0.06, lo, hi)]
png = os.path.join(os.path.dirname(sys.argv[3]), "press_bed_snapshot.png")
render.snapshot(png, render.spheres(atoms), walls, elev=20, azim=-60,
                title=f"t = {step * 1e-5:.3f} s: the plate (MBDyn's body) pressing into the bed")
print(f"{png}: step {step}")
