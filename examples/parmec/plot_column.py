"""Plot of column.py: base and top displacement, top vertical drop, bottom joint reaction; and snapshot.png: the
blocks at the column's largest drift, coloured by speed (the MESH output out/column0.pvd).
Usage: python plot_column.py (run from this folder after column.py; reads out/column_history.csv and out/column0.pvd,
writes column.png and snapshot.png)."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from dembridge import render  # noqa: E402

rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open("out/column_history.csv"))]
t = [r["TIME"] for r in rows]
fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
ax[0].plot(t, [r["base_DX"] for r in rows], label="base DX (prescribed)")
ax[0].plot(t, [r["top_DX"] for r in rows], label="top block DX")
ax[0].set_xlabel("time [s]")
ax[0].set_ylabel("displacement [m]")
ax[0].legend(fontsize=8)
ax[0].set_title("column on a shaking base")
ax[1].plot(t, [r["top_DX"] - r["base_DX"] for r in rows], label="top drift DX(top) - DX(base)")
ax[1].plot(t, [r["top_DZ"] for r in rows], label="top DZ")
ax[1].set_xlabel("time [s]")
ax[1].set_ylabel("[m]")
ax[1].legend(fontsize=8)
ax[2].plot(t, [r["j0_JREAC_X"] for r in rows], label="JREAC_X")
ax[2].plot(t, [r["j0_JREAC_Z"] for r in rows], label="JREAC_Z")
ax[2].set_xlabel("time [s]")
ax[2].set_ylabel("bottom joint reaction [N]")
ax[2].legend(fontsize=8)
fig.tight_layout()
fig.savefig("column.png", dpi=110)
print("wrote column.png")

# the frame of the MESH output nearest the largest drift: the blocks' triangles coloured by their nodes' speed
t_drift = max(rows, key=lambda r: abs(r["top_DX"] - r["base_DX"]))["TIME"]
t_frame, vtu = min(render.read_pvd("out/column0.pvd"), key=lambda f: abs(f[0] - t_drift))
tris, speed = render.read_vtu_mesh(vtu)
render.snapshot("snapshot.png", (np.zeros((0, 3)), np.zeros(0), np.zeros(0)), [(tris, speed)], elev=15, azim=-75,
                title=f"t = {t_frame:.2f} s: the column at its largest drift")
print("wrote snapshot.png")
