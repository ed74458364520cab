"""Plot of in.rocking_block: tilt components and the cone limit. Usage: python plot_rocking.py
(reads torsion_history.csv, writes rocking_block.png)."""
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open("torsion_history.csv"))]
t = [r["TIME"] for r in rows]
roll = [r["trq1_ROLL"] for r in rows]
pitch = [r["trq1_PITCH"] for r in rows]
phi = [math.hypot(a, b) for a, b in zip(roll, pitch)]
trq = [math.hypot(r["trq1_TRQTOT_R"], r["trq1_TRQTOT_P"]) for r in rows]

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
