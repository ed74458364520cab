"""Renders the last frame of a run of in.deck (post/funnel_*.vtk) with the funnel (meshes/funnel.stl),
headless with matplotlib, to funnel.png beside this file (or the path given)."""
import glob
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from dembridge import read_vtk_particles  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def triangles(stl):
    v = [[float(x) for x in ln.split()[1:4]] for ln in open(stl) if ln.strip().startswith("vertex")]
    return np.array(v).reshape(-1, 3, 3)


def frames(folder):
    files = glob.glob(os.path.join(folder, "funnel_*.vtk"))
    return sorted((int(re.search(r"_(\d+)\.vtk$", f).group(1)), f) for f in files if "boundingBox" not in f)


def main(folder=os.path.join(HERE, "post"), out=os.path.join(HERE, "funnel.png")):
    (first, f0), (last, f1) = frames(folder)[0], frames(folder)[-1]
    fig = plt.figure(figsize=(9, 4.6))
    for k, (step, path) in enumerate(((first, f0), (last, f1))):
        p = read_vtk_particles(path)
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        ax.add_collection3d(Poly3DCollection(triangles(os.path.join(HERE, "meshes", "funnel.stl")),
                                             facecolor=(0.6, 0.6, 0.7, 0.25), edgecolor=(0.3, 0.3, 0.4, 0.6)))
        speed = np.linalg.norm(p["v"], axis=1)
        sc = ax.scatter(*p["points"].T, s=(p["radius"] / 0.0025) ** 2 * 6, c=speed, cmap="viridis",
                        vmin=0, vmax=1.2, depthshade=False)
        ax.set_xlim(-0.06, 0.06), ax.set_ylim(-0.06, 0.06), ax.set_zlim(-0.02, 0.16)
        ax.set_box_aspect((0.12, 0.12, 0.18))
        ax.view_init(elev=12, azim=-60)
        ax.set_title(f"step {step}: {len(speed)} particles")
        ax.set_xticks([]), ax.set_yticks([]), ax.set_zticks([])
    fig.colorbar(sc, ax=fig.axes, shrink=0.6, label="speed (m/s)")
    fig.savefig(out, dpi=90)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:])
