"""Headless snapshots of a run for the examples: spheres coloured by their speed, with the meshes and walls
drawn, in an orthographic view, with matplotlib only (Agg).

Spheres are drawn as discs of their true radius and triangles as polygons, all in one collection sorted
far to near (painter's order), so particles in front of a wall hide it and particles behind a translucent
wall show through. Large triangles are split until their edges are short against the scene, so that the
painter's order of a floor and the particles on it is right.

>>> from dembridge import render, read_dump_atoms                       # doctest: +SKIP
>>> step, atoms = read_dump_atoms("out/hopper.dump")[-1]
>>> render.snapshot("out/snapshot.png", render.spheres(atoms), [render.read_stl("funnel.stl")],
...                 title=f"step {step}")

Readers for what the examples write: ``read_stl`` (ASCII or binary), ``read_vtk_mesh`` (legacy VTK
POLYDATA or UNSTRUCTURED_GRID of triangles, as ``fix mesh/dump vtk`` and ``dump mesh/gran/VTK`` write it),
``read_vtu_mesh`` (VTK XML ``.vtu`` of the Parmec front end, with the node velocities), ``read_pvd`` (the frames
of a .pvd time series).
"""
import os
import re
import struct
import xml.etree.ElementTree as ET

import numpy as np

DISC_SIDES = 20  # polygon sides of a sphere's disc
MESH_COLOUR = (0.55, 0.58, 0.66, 0.45)  # translucent grey-blue
MESH_EDGE = (0.2, 0.22, 0.3, 0.8)


# ------------------------------------------------------------------ readers
def read_stl(path):
    """Triangles (T x 3 x 3) of an ASCII or binary STL file."""
    data = open(path, "rb").read()
    if len(data) >= 84:
        n = struct.unpack("<I", data[80:84])[0]
        if 84 + 50 * n == len(data):  # binary: the size says so (an ASCII file starting with "solid" can be binary)
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=n, offset=84)
            return rec["v"].astype(float)
    v = re.findall(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)", data)
    return np.array(v, dtype=float).reshape(-1, 3, 3)


def read_vtk_mesh(path):
    """Triangles (T x 3 x 3) of a legacy ASCII VTK file of a triangle mesh (POLYDATA with POLYGONS, or
    UNSTRUCTURED_GRID with CELLS)."""
    tok = open(path).read().split()
    pts, tris = None, []
    k = 0
    while k < len(tok):
        t = tok[k]
        if t == "POINTS":
            n = int(tok[k + 1])
            pts = np.array(tok[k + 3:k + 3 + 3 * n], dtype=float).reshape(n, 3)
            k += 3 + 3 * n
        elif t in ("POLYGONS", "CELLS"):
            ncell, size = int(tok[k + 1]), int(tok[k + 2])
            ids = np.array(tok[k + 3:k + 3 + size], dtype=np.int64)
            j = 0
            for _ in range(ncell):
                m = ids[j]
                if m == 3:
                    tris.append(ids[j + 1:j + 4])
                j += m + 1
            k += 3 + size
        else:
            k += 1
    if pts is None:
        raise ValueError(f"{path}: no POINTS in this VTK file")
    return pts[np.array(tris, dtype=np.int64).reshape(-1, 3)]


def read_vtu_mesh(path, velocity="LINVEL"):
    """(triangles T x 3 x 3, speed per triangle: the mean of its nodes' speeds) of a VTK XML .vtu file of
    triangles with ASCII data arrays (as the Parmec front end's MESH output)."""
    piece = ET.parse(path).getroot().find(".//Piece")

    def array(section, name):
        for a in piece.findall(f"{section}/DataArray"):
            if a.get("Name") == name:
                return np.array(a.text.split(), dtype=float)
        return None
    pts = np.array(piece.find("Points/DataArray").text.split(), dtype=float).reshape(-1, 3)
    conn = array("Cells", "connectivity").astype(np.int64)
    offs = array("Cells", "offsets").astype(np.int64)
    starts = np.concatenate(([0], offs[:-1]))
    tri = np.array([conn[s:s + 3] for s, e in zip(starts, offs) if e - s == 3], dtype=np.int64).reshape(-1, 3)
    vel = array("PointData", velocity)
    speed = None
    if vel is not None:
        node_speed = np.linalg.norm(vel.reshape(-1, 3), axis=1)
        speed = node_speed[tri].mean(axis=1)
    return pts[tri], speed


def read_pvd(path):
    """[(time, path of the frame)] of a ParaView .pvd time series, in time order."""
    root = ET.parse(path).getroot()
    folder = os.path.dirname(os.path.abspath(path))
    return sorted((float(d.get("timestep")), os.path.join(folder, d.get("file"))) for d in root.iter("DataSet"))


# ------------------------------------------------------------------ scene pieces
def spheres(atoms, mask=None):
    """(positions N x 3, radii N, speeds N) of a ``read_dump_atoms`` frame (columns x y z, radius, and
    vx vy vz when dumped: else speed 0), the atoms selected by ``mask`` (all by default)."""
    x = np.column_stack([atoms["x"], atoms["y"], atoms["z"]])
    r = np.asarray(atoms["radius"], dtype=float) if "radius" in atoms else np.full(len(x), 0.5 * 1e-3)
    v = (np.linalg.norm(np.column_stack([atoms["vx"], atoms["vy"], atoms["vz"]]), axis=1) if "vx" in atoms
         else np.zeros(len(x)))
    if mask is not None:
        x, r, v = x[mask], r[mask], v[mask]
    return x, r, v


def plane(axis, value, lo, hi):
    """Two triangles of the rectangle ``axis`` = value (a primitive wall) spanning ``lo``..``hi`` (3-vectors;
    the ``axis`` component is ignored)."""
    a = "xyz".index(axis)
    u, w = [i for i in range(3) if i != a]
    corners = []
    for cu, cw in ((lo[u], lo[w]), (hi[u], lo[w]), (hi[u], hi[w]), (lo[u], hi[w])):
        p = [0.0, 0.0, 0.0]
        p[a], p[u], p[w] = value, cu, cw
        corners.append(p)
    c = np.array(corners)
    return np.array([[c[0], c[1], c[2]], [c[0], c[2], c[3]]])


def _split(tris, max_edge):
    """Triangles split in four (edge midpoints) until every edge is at most ``max_edge``."""
    out = []
    todo = [np.asarray(t, dtype=float) for t in tris]
    while todo:
        t = todo.pop()
        e = max(np.linalg.norm(t[1] - t[0]), np.linalg.norm(t[2] - t[1]), np.linalg.norm(t[0] - t[2]))
        if e <= max_edge or len(out) + len(todo) > 200000:
            out.append(t)
            continue
        a, b, c = t
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        todo += [np.array(q) for q in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))]
    return np.array(out).reshape(-1, 3, 3)


def _camera(elev, azim):
    """Unit vectors (right, up, toward the viewer) of a view from azimuth ``azim`` and elevation ``elev``
    (degrees; as matplotlib's 3-D axes: z up)."""
    e, a = np.radians(elev), np.radians(azim)
    toward = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    up = np.cross(toward, right)
    return right, up, toward


# ------------------------------------------------------------------ drawing
def draw(ax, balls, meshes=(), lines=(), elev=20, azim=-60, vmax=None, cmap="viridis", up="z"):
    """Draws a scene on the 2-D axes ``ax`` and returns the ScalarMappable of the speed colours.

    balls: (positions N x 3, radii N, speeds N), e.g. ``spheres(frame)``;
    meshes: triangle arrays (T x 3 x 3), grey and translucent, or (triangles, speeds per triangle) pairs,
    coloured by speed like the spheres; lines: segments (S x 2 x 3), e.g. springs, drawn on top;
    elev, azim: the view (degrees); up: the scene's vertical axis ("z", or "y" for a deck with gravity along
    -y); vmax: top of the colour scale (default: the largest speed)."""
    import matplotlib
    from matplotlib.collections import LineCollection, PolyCollection

    perm = {"z": [0, 1, 2], "y": [2, 0, 1], "x": [1, 2, 0]}[up]  # scene axes -> view axes with `up` as z
    x, r, v = (np.asarray(balls[0], dtype=float).reshape(-1, 3)[:, perm], np.asarray(balls[1], dtype=float),
               np.asarray(balls[2], dtype=float))
    mesh_list = [(np.asarray(m, dtype=float)[..., perm], None) if not isinstance(m, tuple) else
                 (np.asarray(m[0], dtype=float)[..., perm], np.asarray(m[1], dtype=float)) for m in meshes]
    right, upv, toward = _camera(elev, azim)
    pts = [x] + [m.reshape(-1, 3) for m, _ in mesh_list]
    allp = np.concatenate([p for p in pts if len(p)]) if any(len(p) for p in pts) else np.zeros((1, 3))
    span = float(np.max(allp.max(axis=0) - allp.min(axis=0))) or 1.0
    speeds = [v] + [s for _, s in mesh_list if s is not None]
    top = vmax if vmax is not None else max([float(np.max(s)) for s in speeds if len(s)] + [1e-12])
    norm = matplotlib.colors.Normalize(vmin=0.0, vmax=top)
    colours = matplotlib.colormaps[cmap]

    polys, faces, edges, depth = [], [], [], []
    ang = np.linspace(0, 2 * np.pi, DISC_SIDES, endpoint=False)
    ring = np.column_stack([np.cos(ang), np.sin(ang)])
    if len(x):
        centre = np.column_stack([x @ right, x @ upv])
        discs = centre[:, None, :] + r[:, None, None] * ring[None, :, :]
        polys += list(discs)
        faces += list(colours(norm(v)))
        edges += [(0.1, 0.1, 0.15, 0.8)] * len(x)
        depth += list(x @ toward + r)
    for tris, speed in mesh_list:
        if speed is None:
            tris = _split(tris, span / 25)
        if not len(tris):
            continue
        polys += list(np.stack([tris @ right, tris @ upv], axis=-1))
        if speed is None:
            faces += [MESH_COLOUR] * len(tris)
            edges += [MESH_EDGE if len(tris) < 400 else (0, 0, 0, 0)] * len(tris)
        else:
            faces += list(colours(norm(speed)))
            edges += [(0.1, 0.1, 0.15, 0.5)] * len(tris)
        depth += list(tris.mean(axis=1) @ toward)
    order = np.argsort(depth, kind="stable")
    if len(order):
        ax.add_collection(PolyCollection([polys[i] for i in order], facecolors=np.asarray(faces)[order],
                                         edgecolors=np.asarray(edges)[order], linewidths=0.3))
    if len(lines):
        seg = np.asarray(lines, dtype=float)[..., perm]
        ax.add_collection(LineCollection(np.stack([seg @ right, seg @ upv], axis=-1), colors="0.2", linewidths=0.8))
    flat = np.stack([allp @ right, allp @ upv], axis=-1)
    pad = (r.max() if len(r) else 0.0) + 0.03 * span
    (x0, y0), (x1, y1) = flat.min(axis=0) - pad, flat.max(axis=0) + pad
    w, h = x1 - x0, y1 - y0  # widened (or heightened) to an aspect of 0.8-2.2, so a tall chain keeps room around it
    if w < 0.8 * h:
        x0, x1 = x0 - (0.8 * h - w) / 2, x1 + (0.8 * h - w) / 2
    elif w > 2.2 * h:
        y0, y1 = y0 - (w / 2.2 - h) / 2, y1 + (w / 2.2 - h) / 2
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    for s in ax.spines.values():
        s.set_visible(False)
    return matplotlib.cm.ScalarMappable(norm=norm, cmap=colours)


def snapshot(png, balls, meshes=(), lines=(), title=None, size=(6.4, 4.8), dpi=100, unit="m/s", **view):
    """Writes ``png``: one scene (see ``draw``) with a colour bar of the speed and a scale bar. Returns png."""
    from .plotting import pyplot
    plt = pyplot()
    fig, ax = plt.subplots(figsize=size)
    sm = draw(ax, balls, meshes, lines, **view)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    if size == (6.4, 4.8):  # the default: as wide as the scene is (room for the colour bar), within 5-9 inches
        fig.set_size_inches(min(9.0, max(5.0, 4.4 * (x1 - x0) / (y1 - y0) + 1.6)), 4.8)
    fig.colorbar(sm, ax=ax, shrink=0.75, label=f"speed ({unit})")
    _scale_bar(ax)
    if title:
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=dpi)
    plt.close(fig)
    return png


def _scale_bar(ax):
    """A bar of a round length (1, 2 or 5 times a power of ten) in the lower left corner."""
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    want = 0.2 * (x1 - x0)
    p = 10 ** np.floor(np.log10(want))
    length = max(m * p for m in (1, 2, 5) if m * p <= want)
    text = f"{length * 1e3:g} mm" if length < 1 else f"{length:g} m"
    ax.plot([x0 + 0.03 * (x1 - x0), x0 + 0.03 * (x1 - x0) + length], [y0 + 0.03 * (y1 - y0)] * 2, color="k", lw=2)
    ax.text(x0 + 0.03 * (x1 - x0) + length / 2, y0 + 0.05 * (y1 - y0), text, ha="center", va="bottom", fontsize=8)
