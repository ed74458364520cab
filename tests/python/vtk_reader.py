"""A small VTK XML reader for the Parmec front end's OUTPUT tests (.vtu UnstructuredGrid and .pvd
collections, ASCII): parsing with xml.etree also checks that the files are well-formed XML."""
import os
import xml.etree.ElementTree as ET


def read_vtu(path):
    """{'points': [(x, y, z)], 'cells': [[...]], 'types': [...], 'point': {name: rows}, 'cell': {name: rows}}."""
    piece = ET.parse(path).getroot().find("UnstructuredGrid/Piece")

    def arr(e):
        n = int(e.get("NumberOfComponents", "1"))
        conv = float if e.get("type").startswith("Float") else int
        vals = [conv(v) for v in e.text.split()]
        return [vals[k:k + n] for k in range(0, len(vals), n)]

    out = {"points": arr(piece.find("Points/DataArray")), "point": {}, "cell": {}}
    cells = {e.get("Name"): arr(e) for e in piece.find("Cells")}
    conn, offs = [c[0] for c in cells["connectivity"]], [o[0] for o in cells["offsets"]]
    out["cells"] = [conn[a:b] for a, b in zip([0] + offs[:-1], offs)]
    out["types"] = [t[0] for t in cells["types"]]
    for tag, key in (("PointData", "point"), ("CellData", "cell")):
        for e in piece.find(tag) or []:
            out[key][e.get("Name")] = arr(e)
    assert len(out["points"]) == int(piece.get("NumberOfPoints"))
    assert len(out["cells"]) == int(piece.get("NumberOfCells"))
    return out


def read_pvd(path):
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), os.path.join(os.path.dirname(path), d.get("file")))
            for d in root.find("Collection")]


def read_legacy(path):
    """A legacy ASCII VTK file (version 5.1, as LIGGGHTS's and dembridge's dumps write it):
    {'version', 'title', 'dataset', 'points': [[x, y, z]], 'arrays': {name: (components, type, rows)},
    'order': [array names in file order], 'coordinates': {'X': [...], ...}} (RECTILINEAR_GRID)."""
    lines = open(path).read().split("\n")
    out = {"version": lines[0], "title": lines[1], "points": [], "arrays": {}, "order": [], "coordinates": {}}
    assert lines[2] == "ASCII", lines[2]
    out["dataset"] = lines[3].split()[1]
    tokens = " ".join(lines[4:]).split()
    k = 0

    def take(n, conv):
        nonlocal k
        vals = [conv(t) for t in tokens[k:k + n]]
        assert len(vals) == n, f"{path}: file ends inside a block"
        k += n
        return vals
    while k < len(tokens):
        key = tokens[k]
        if key == "POINTS":
            n, k = int(tokens[k + 1]), k + 3
            v = take(3 * n, float)
            out["points"] = [v[i:i + 3] for i in range(0, 3 * n, 3)]
        elif key == "VERTICES":
            noff, nconn, k = int(tokens[k + 1]), int(tokens[k + 2]), k + 3
            assert tokens[k:k + 2] == ["OFFSETS", "vtktypeint64"]
            k += 2
            out["offsets"] = take(noff, int)
            assert tokens[k:k + 2] == ["CONNECTIVITY", "vtktypeint64"]
            k += 2
            out["connectivity"] = take(nconn, int)
        elif key == "POINT_DATA":
            out["npoint_data"], k = int(tokens[k + 1]), k + 2
        elif key == "FIELD":
            narr, k = int(tokens[k + 2]), k + 3
            for _ in range(narr):
                name, comps, ntup, typ = tokens[k:k + 4]
                k += 4
                v = take(int(comps) * int(ntup), int if typ == "int" else float)
                c = int(comps)
                out["arrays"][name] = (c, typ, [v[i:i + c] for i in range(0, len(v), c)])
                out["order"].append(name)
        elif key == "DIMENSIONS":
            out["dimensions"], k = [int(t) for t in tokens[k + 1:k + 4]], k + 4
        elif key.endswith("_COORDINATES"):
            n, k = int(tokens[k + 1]), k + 3
            out["coordinates"][key[0]] = take(n, float)
        else:
            raise AssertionError(f"{path}: unexpected token {key!r}")
    return out
