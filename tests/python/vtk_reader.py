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
