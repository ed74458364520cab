"""Plot of in.failing_chain: link forces, state codes and the bottom body. Usage: python plot_failing_chain.py
(reads chain_history.csv and chain_atoms.dump, writes failing_chain.png and snapshot.png: the chain 0.1 s after
link 6 failed, the bodies coloured by speed, the links drawn)."""
import csv
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from dembridge import read_dump_atoms, render  # noqa: E402

rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open("chain_history.csv"))]
t = [r["TIME"] for r in rows]
zb, tz = [], []
lines = open("chain_atoms.dump").read().split("\n")
for i, l in enumerate(lines):
    if l.startswith("ITEM: TIMESTEP"):
        step = int(lines[i + 1])
    if l.startswith("ITEM: ATOMS"):
        n = int(lines[i - 5])
        for row in lines[i + 1:i + 1 + n]:
            a = row.split()
            if a[0] == "10":
                tz.append(step * 1e-3)
                zb.append(float(a[1]))

fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
for s, lab in [(5, "link 5 (bodies 4-5)"), (6, "link 6 (bodies 5-6, tested)"), (7, "link 7 (bodies 6-7)"),
               (11, "backup rope 11")]:
    ax[0].plot(t, [r[f"spr{s}_SF"] for r in rows], lw=0.9, label=lab)
ax[0].axhline(1200, color="r", ls="--", lw=0.8, label="UNSPRING limit 1200 N")
ax[0].set_xlabel("time [s]")
ax[0].set_ylabel("SF [N]")
ax[0].legend(fontsize=8)
ax[0].set_title("link forces (gravity 9.81 (1 + 2t))")
for s in (6, 11):
    ax[1].step(t, [r[f"spr{s}_SS"] for r in rows], where="post", label=f"spring {s}")
ax[1].set_yticks([-3, -2, -1, 0, 1])
ax[1].set_xlabel("time [s]")
ax[1].set_ylabel("state code SS")
ax[1].legend(fontsize=8)
ax[1].set_title("-2 managed, 1 unloading (TSERIES 1), -1 removed, -3 active")
ax[2].plot(tz, zb, lw=0.9)
ax[2].set_xlabel("time [s]")
ax[2].set_ylabel("z of body 10 [m]")
ax[2].set_title("body 10: drops at the failure, rope catches")
fig.tight_layout()
fig.savefig("failing_chain.png", dpi=110)
fail = next(r["TIME"] for r in rows if r["spr6_SS"] != -2)
print(f"failing_chain.png: {len(rows)} rows; link 6 left state -2 at t = {fail:.3f} s")

# snapshot: the chain 0.1 s after link 6 failed, links as lines
frames = read_dump_atoms("chain_atoms.dump")
step, atoms = min(frames, key=lambda f: abs(f[0] * 1e-3 - (fail + 0.1))) 
x = np.column_stack([atoms["x"], atoms["y"], atoms["z"]])
links = np.stack([np.vstack([[0.0, 0.0, 1.0], x[:-1]]), x], axis=1)  # spring 1 from a point in space, links 2-10
render.snapshot("snapshot.png", render.spheres(atoms), lines=links, elev=10, azim=-80,
                title=f"t = {step * 1e-3:.2f} s: link 6 failed, the rope holds the lower half")
print("snapshot.png: step", step)
