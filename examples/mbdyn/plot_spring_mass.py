"""Case b: MBDyn's trajectory of the split spring-mass vs the analytic damped oscillation.
usage: python plot_spring_mass.py TRAJECTORY.txt OUT.png   (trajectory: t x y z ... per line, as
written by mbdyn_testpeer --trajectory; from real MBDyn use columns t, x of the node's .mov output)"""
import math
import sys

M, K, C, X0 = 2.0, 50.0, 0.4, 0.1


def analytic(t):
    w0 = math.sqrt(K / M)
    z = C / (2 * math.sqrt(K * M))
    wd = w0 * math.sqrt(1 - z * z)
    return math.exp(-z * w0 * t) * (X0 * math.cos(wd * t) + z * w0 * X0 / wd * math.sin(wd * t))


rows = [[float(v) for v in l.split()] for l in open(sys.argv[1]) if l.strip() and not l.startswith("#")]
t = [r[0] for r in rows]
x = [r[1] for r in rows]
xa = [analytic(s) for s in t]
err = max(abs(a - b) for a, b in zip(x, xa))
print(f"max |x - x_analytic| = {err:.3e} over {len(t) - 1} MBDyn steps")

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
ax1.plot(t, xa, "k-", lw=1, label="analytic")
ax1.plot(t[::5], x[::5], "o", ms=3, mfc="none", label="MBDyn mass + LAMMPS spring/dashpot")
ax1.set_ylabel("x [m]")
ax1.legend()
ax2.plot(t, [a - b for a, b in zip(x, xa)])
ax2.set_ylabel("x - x_analytic [m]")
ax2.set_xlabel("t [s]")
fig.suptitle("split spring-mass, loose coupling (fix mbdyn)")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=100)
