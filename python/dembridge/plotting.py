"""Plotting helpers shared by the examples (matplotlib, headless)."""


def pyplot():
    """matplotlib.pyplot with the non-interactive Agg backend (examples run on machines without a display)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def energy_history(ax, thermo, dt, columns, labels=None, floor=1e-30):
    """Semilog plot of thermo ``columns`` against time ``Step * dt`` (e.g. KinEng and rotational KE)."""
    t = thermo["Step"] * dt
    for k, c in enumerate(columns):
        ax.semilogy(t, [max(v, floor) for v in thermo[c]], label=(labels or columns)[k])
    ax.set_xlabel("time")
    ax.legend()
    return ax


def packing_slice(ax, frame, axis="y", thickness=None, cmap="viridis"):
    """Spheres of a ``dump custom`` frame (``x y z radius``) cut by a slab through the middle of
    ``axis``, drawn as circles coloured by radius in the plane of the other two axes."""
    import numpy as np
    plt = pyplot()
    other = [a for a in "xyz" if a != axis]
    c, r = frame[axis], frame["radius"]
    mid = 0.5 * (c.min() + c.max())
    half = 0.5 * (thickness if thickness is not None else 3 * r.max())
    sel = np.abs(c - mid) < half
    lo, hi = r.min(), r.max()
    colours = plt.get_cmap(cmap)
    for u, v, rad in zip(frame[other[0]][sel], frame[other[1]][sel], r[sel]):
        ax.add_patch(plt.Circle((u, v), rad, color=colours((rad - lo) / (hi - lo) if hi > lo else 0.5), alpha=0.8))
    ax.set_xlim(0, (frame[other[0]] + r).max())
    ax.set_ylim(0, (frame[other[1]] + r).max())
    ax.set_aspect("equal")
    ax.set_xlabel(other[0])
    ax.set_ylabel(other[1])
    return int(sel.sum())


def force_stroke(ax, stroke, force, label=None):
    """Force against stroke of one spring (a hysteresis loop)."""
    ax.plot(stroke, force, lw=0.8, label=label)
    ax.set_xlabel("STROKE")
    ax.set_ylabel("force")
    return ax
