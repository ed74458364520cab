"""Force-stroke loop of one spring from springs.dump (written by in.chain). Usage: python plot_hysteresis.py [SPRID]"""
import sys

import matplotlib.pyplot as plt

sid = int(sys.argv[1]) if len(sys.argv) > 1 else 7
stroke, force = [], []
lines = open("springs.dump").read().split("\n")
for i, l in enumerate(lines):
    if l.startswith("ITEM: ENTRIES"):
        j = i + 1
        while j < len(lines) and lines[j] and not lines[j].startswith("ITEM"):
            v = lines[j].split()
            if int(float(v[0])) == sid:
                stroke.append(float(v[2]))
                force.append(float(v[4]))
            j += 1
plt.plot(stroke, force, lw=0.8)
plt.xlabel("STROKE [m]")
plt.ylabel("SF [N]")
plt.title(f"spring {sid}")
plt.savefig(f"hysteresis_{sid}.png", dpi=120)
print(f"hysteresis_{sid}.png: {len(stroke)} samples")
