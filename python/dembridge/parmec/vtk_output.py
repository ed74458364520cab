"""OUTPUT(format='VTK'): ParaView files of a Parmec run, one frame per output time.

Rigid-body frames (one vertex per particle at its mass centre with NUMBER, COLOR, DISPL, ORIENT (9
components, rows of Λ), ORIENT1/2/3 (columns of Λ), LINVEL, ANGVEL, FORCE, TORQUE and RADIUS for glyphs) and
MESH frames (boundary faces as triangles at the current configuration x + Λ(P − X), NUMBER and COLOR per
triangle, DISPL, LINVEL per node); which files hold them: output_files.py. Files are VTK XML
UnstructuredGrid (ASCII, 17 significant digits) collected with their times in a .pvd, which ParaView opens
as a time series."""

_FACES = {
    4: [(1, 3, 2), (1, 2, 4), (2, 3, 4), (3, 1, 4)],
    5: [(1, 4, 3, 2), (1, 2, 5), (2, 3, 5), (3, 4, 5), (4, 1, 5)],
    6: [(1, 3, 2), (4, 5, 6), (1, 2, 5, 4), (2, 3, 6, 5), (3, 1, 4, 6)],
    8: [(1, 4, 3, 2), (1, 2, 6, 5), (2, 3, 7, 6), (3, 4, 8, 7), (1, 5, 8, 4), (5, 6, 7, 8)],
}
RB_ENTITIES = ("NUMBER", "COLOR", "DISPL", "ORIENT", "ORIENT1", "ORIENT2", "ORIENT3", "LINVEL", "ANGVEL", "FORCE",
               "TORQUE")


def boundary_faces(elements):
    """Outward boundary faces (node index lists) of a Parmec element list [n, i1..in, mat, ...]: the faces
    that belong to one element only."""
    faces, k = [], 0
    while k < len(elements):
        n = int(elements[k])
        ids = [int(e) for e in elements[k + 1:k + 1 + n]]
        faces += [[ids[v - 1] for v in f] for f in _FACES[n]]
        k += n + 2
    count = {}
    for f in faces:
        key = tuple(sorted(f))
        count[key] = count.get(key, 0) + 1
    return [f for f in faces if count[tuple(sorted(f))] == 1]


def fan(face):
    """The triangles of a face, fanned from its first node."""
    return [(face[0], face[j], face[j + 1]) for j in range(1, len(face) - 1)]


def _fmt(v):
    return repr(float(v))


def _array(name, rows, ncomp, kind="Float64"):
    body = "\n".join(" ".join(_fmt(c) if kind == "Float64" else str(int(c)) for c in r) for r in rows)
    return (f'<DataArray type="{kind}" Name="{name}" NumberOfComponents="{ncomp}" format="ascii">\n'
            f'{body}\n</DataArray>\n')


def write_vtu(path, points, cells, cell_type, point_data=(), cell_data=()):
    """points: [(x, y, z)]; cells: [(i, j, ...)] of one VTK cell type; *_data: [(name, ncomp, rows, kind)]."""
    offsets, acc = [], 0
    for c in cells:
        acc += len(c)
        offsets.append(acc)
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">\n'
                f'<UnstructuredGrid>\n<Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(cells)}">\n')
        f.write("<Points>\n" + _array("Points", points, 3) + "</Points>\n")
        f.write("<Cells>\n" + _array("connectivity", cells, 1, "Int64").replace('NumberOfComponents="1" ', "")
                + _array("offsets", [[o] for o in offsets], 1, "Int64").replace('NumberOfComponents="1" ', "")
                + _array("types", [[cell_type] for _ in cells], 1, "UInt8").replace('NumberOfComponents="1" ', "")
                + "</Cells>\n")
        for tag, data in (("PointData", point_data), ("CellData", cell_data)):
            f.write(f"<{tag}>\n" + "".join(_array(n, rows, k, kind) for n, k, rows, kind in data) + f"</{tag}>\n")
        f.write("</Piece>\n</UnstructuredGrid>\n</VTKFile>\n")


def write_pvd(path, frames):
    """frames: [(time, file name relative to the .pvd)]."""
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
                "<Collection>\n")
        for t, name in frames:
            f.write(f'<DataSet timestep="{_fmt(t)}" group="" part="0" file="{name}"/>\n')
        f.write("</Collection>\n</VTKFile>\n")


def _columns(L):
    return [[L[0][c], L[1][c], L[2][c]] for c in range(3)]


def rigid_body_frame(path, particles, ids, states, entities):
    """One rigid-body frame: states[i] = {x, v, w, f, t, L (rows)} of particle i."""
    pts = [states[i]["x"] for i in ids]
    want = set(entities or RB_ENTITIES)
    data = []
    if "NUMBER" in want:
        data.append(("NUMBER", 1, [[i] for i in ids], "Int32"))
    if "COLOR" in want:
        data.append(("COLOR", 1, [[particles[i].color] for i in ids], "Int32"))
    if "DISPL" in want:
        data.append(("DISPL", 3, [[states[i]["x"][c] - particles[i].centre[c] for c in range(3)] for i in ids], "Float64"))
    if "ORIENT" in want:
        data.append(("ORIENT", 9, [[v for r in states[i]["L"] for v in r] for i in ids], "Float64"))
    for k in range(3):
        if f"ORIENT{k + 1}" in want:
            data.append((f"ORIENT{k + 1}", 3, [_columns(states[i]["L"])[k] for i in ids], "Float64"))
    for name, key in (("LINVEL", "v"), ("ANGVEL", "w"), ("FORCE", "f"), ("TORQUE", "t")):
        if name in want:
            data.append((name, 3, [states[i][key] for i in ids], "Float64"))
    data.append(("RADIUS", 1, [[particles[i].radius] for i in ids], "Float64"))
    write_vtu(path, pts, [[k] for k in range(len(ids))], 1, point_data=data)


def mesh_frame(path, particles, ids, states, entities, obstacles=()):
    """One frame of the MESH particles among ids: boundary triangles at x + Λ(P − X); first the triangles of
    the obstacles given ({triangles, colors}: NUMBER -1 as Parmec's static-obstacle owner, zero DISPL and
    LINVEL)."""
    pts, tris, number, color, displ, linvel = [], [], [], [], [], []
    want = set(entities or RB_ENTITIES)
    for ob in obstacles:
        for t, c in zip(ob["triangles"], ob["colors"]):
            tris.append([len(pts), len(pts) + 1, len(pts) + 2])
            pts += [list(t[0:3]), list(t[3:6]), list(t[6:9])]
            displ += [[0.0] * 3] * 3
            linvel += [[0.0] * 3] * 3
            number.append([-1])
            color.append([c])
    for i in ids:
        p = particles[i]
        if p.kind != "MESH":
            continue
        st, X = states[i], p.centre
        base = len(pts)
        for n in range(len(p.nodes) // 3):
            P = p.nodes[3 * n:3 * n + 3]
            a = [sum(st["L"][r][c] * (P[c] - X[c]) for c in range(3)) for r in range(3)]
            q = [st["x"][r] + a[r] for r in range(3)]
            pts.append(q)
            displ.append([q[r] - P[r] for r in range(3)])
            w = st["w"]
            linvel.append([st["v"][0] + w[1] * a[2] - w[2] * a[1], st["v"][1] + w[2] * a[0] - w[0] * a[2],
                           st["v"][2] + w[0] * a[1] - w[1] * a[0]])
        for t, c in zip(p.triangles, p.triangle_colors):
            tris.append([base + t[0], base + t[1], base + t[2]])
            number.append([i])
            color.append([c])
    if not tris:
        return False
    pdata = [d for d in (("DISPL", 3, displ, "Float64"), ("LINVEL", 3, linvel, "Float64")) if d[0] in want]
    cdata = [d for d in (("NUMBER", 1, number, "Int32"), ("COLOR", 1, color, "Int32")) if d[0] in want]
    write_vtu(path, pts, tris, 5, point_data=pdata, cell_data=cdata)
    return True
