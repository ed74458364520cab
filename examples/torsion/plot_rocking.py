"""Plot of in.rocking_block: tilt components and the cone limit. Usage: python plot_rocking.py
(reads torsion_history.csv, writes rocking_block.png)."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from dembridge import plotting, read_history_csv  # noqa: E402

plt = plotting.pyplot()
h = read_history_csv("torsion_history.csv")
t, roll, pitch = h["TIME"], h["trq1_ROLL"], h["trq1_PITCH"]
phi = np.hypot(roll, pitch)
trq = np.hypot(h["trq1_TRQTOT_R"], h["trq1_TRQTOT_P"])
rows = t

fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
ax[0].plot(t, roll, lw=0.8, label="ROLL")
ax[0].plot(t, pitch, lw=0.8, label="PITCH")
ax[0].plot(t, phi, lw=1.2, color="k", label="tilt sqrt(ROLL²+PITCH²)")
ax[0].axhline(0.1, color="r", ls="--", lw=0.8, label="cone limit 0.1 rad")
ax[0].set_xlabel("time [s]")
ax[0].set_ylabel("angle [rad]")
ax[0].legend(fontsize=8)
ax[0].set_title("rocking block: torsion angles")
th = [2 * math.pi * k / 200 for k in range(201)]
ax[1].plot(roll, pitch, lw=0.6)
ax[1].plot([0.1 * math.cos(a) for a in th], [0.1 * math.sin(a) for a in th], "r--", lw=0.8, label="cone limit")
ax[1].set_aspect("equal")
ax[1].set_xlabel("ROLL [rad]")
ax[1].set_ylabel("PITCH [rad]")
ax[1].legend(fontsize=8)
ax[1].set_title("path in the (roll, pitch) cone")
ax[2].plot(phi, trq, ".", ms=1.5)
ax[2].set_xlabel("tilt [rad]")
ax[2].set_ylabel("|cone torque| [N m]")
ax[2].set_title("cone torque vs tilt (table CONE + damper)")
fig.tight_layout()
fig.savefig("rocking_block.png", dpi=110)
print(f"rocking_block.png: {len(rows)} rows, max tilt {max(phi):.4f} rad")
