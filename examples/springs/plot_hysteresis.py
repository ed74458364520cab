"""Force-stroke loop of one spring from springs.dump (written by in.chain). Usage: python plot_hysteresis.py [SPRID]"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from dembridge import plotting, read_dump_local  # noqa: E402
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
