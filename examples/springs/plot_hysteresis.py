"""Force-stroke loop of one spring from springs.dump (written by in.chain), and snapshot.png: the chain (chain.dump)
at its fastest swing, the spheres coloured by speed, the neighbour springs drawn. Usage: python plot_hysteresis.py [SPRID]"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from dembridge import plotting, read_dump_atoms, read_dump_local, render  # noqa: E402
from dembridge.session import SPRING_LOCAL_COLUMNS  # noqa: E402

sid = int(sys.argv[1]) if len(sys.argv) > 1 else 7
frames = [f for _, f in read_dump_local("springs.dump", SPRING_LOCAL_COLUMNS)]
stroke = np.concatenate([f["STROKE"][f["id"] == sid] for f in frames])
force = np.concatenate([f["SF"][f["id"] == sid] for f in frames])
plt = plotting.pyplot()
fig, ax = plt.subplots()
plotting.force_stroke(ax, stroke, force)
ax.set_xlabel("STROKE [m]")
ax.set_ylabel("SF [N]")
ax.set_title(f"spring {sid}")
fig.savefig(f"hysteresis_{sid}.png", dpi=120)
print(f"hysteresis_{sid}.png: {len(stroke)} samples")

# the frame of the fastest swing: the spheres coloured by speed, the neighbour springs as lines, gravity along -y
step, atoms = max(read_dump_atoms("chain.dump"), key=lambda f: float((f[1]["vx"] ** 2 + f[1]["vy"] ** 2).sum()))
x = np.column_stack([atoms["x"], atoms["y"], atoms["z"]])
render.snapshot("snapshot.png", render.spheres(atoms), lines=np.stack([x[:-1], x[1:]], axis=1), up="y", elev=0,
                azim=0, title=f"t = {step * 1e-3:.1f} s: the chain at its fastest swing")
print("snapshot.png: step", step)
