"""Renders the first and the last frame of a run of in.deck (post/funnel_*.vtk) with the funnel
(meshes/funnel.stl), the particles coloured by speed, headless with matplotlib (dembridge.render), to funnel.png
beside this file (or the path given)."""
import glob
import os
import re
import sys

import numpy as np

from dembridge import plotting, read_vtk_particles, render

HERE = os.path.dirname(os.path.abspath(__file__))


def frames(folder):
    files = glob.glob(os.path.join(folder, "funnel_*.vtk"))
    return sorted((int(re.search(r"_(\d+)\.vtk$", f).group(1)), f) for f in files if "boundingBox" not in f)


def main(folder=os.path.join(HERE, "post"), out=os.path.join(HERE, "funnel.png")):
    plt = plotting.pyplot()
    funnel = render.read_stl(os.path.join(HERE, "meshes", "funnel.stl"))
    floor = render.plane("z", -0.02, (-0.06, -0.06, 0), (0.06, 0.06, 0))  # the primitive zplane wall
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.6))
    for ax, (step, path) in zip(axes, (frames(folder)[0], frames(folder)[-1])):
        p = read_vtk_particles(path)
        speed = np.linalg.norm(p["v"], axis=1)
        sm = render.draw(ax, (p["points"], p["radius"], speed), [funnel, floor], elev=12, azim=-60, vmax=1.2)
        ax.set_title(f"step {step}: {len(speed)} particles")
    for get, put in (("get_xlim", "set_xlim"), ("get_ylim", "set_ylim")):  # one scale for both frames
        lims = [getattr(ax, get)() for ax in axes]
        for ax in axes:
            getattr(ax, put)(min(l[0] for l in lims), max(l[1] for l in lims))
    fig.colorbar(sm, ax=list(axes), shrink=0.6, label="speed (m/s)")
    fig.savefig(out, dpi=90)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:])
