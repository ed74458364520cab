"""Mesh element values at full precision from a LIGGGHTS 3.8 binary restart file (write_restart).

LIGGGHTS prints mesh element values (wear, stress) with 11 significant digits in its mesh dumps, but its
restart file holds them as the doubles themselves. Layout, read from LIGGGHTS-PUBLIC's write_restart,
Modify::write_restart, FixMesh::write_restart and MultiNodeMeshParallel / TrackingMesh::pushElemToBuffer:

  int n, fix ID (n chars with its NUL), int n, fix style (likewise), int nbytes, then nbytes/8 doubles:
    nelements, per-element record size sE, mesh-property size sM,
    nelements records of 1 + sE doubles: [1 + sE, the 9 node coordinates, the element properties added
      with "restart_yes" in the order they were added: TrackingMesh's "id", then (fix mesh/surface/stress
      ... wear finnie) "wear"],
    sM doubles of global mesh properties.
Read-only, for tests; nothing of LIGGGHTS's is reused."""
import struct
from pathlib import Path


def _fix_record(blob: bytes, fix_id: str, style: str) -> list:
    def word(s):
        b = s.encode() + b"\0"
        return struct.pack("<i", len(b)) + b
    key = word(fix_id) + word(style)
    at = blob.find(key)
    if at < 0 or blob.find(key, at + 1) >= 0:
        raise ValueError(f"fix {fix_id} ({style}) found {'no' if at < 0 else 'more than one'} time in the restart file")
    at += len(key)
    (nbytes,) = struct.unpack_from("<i", blob, at)
    if nbytes % 8 or at + 4 + nbytes > len(blob):
        raise ValueError(f"fix {fix_id}: restart record of {nbytes} bytes does not fit the file")
    return list(struct.unpack_from(f"<{nbytes // 8}d", blob, at + 4))


def mesh_elements(path, fix_id: str, style: str = "mesh/surface/stress"):
    """[(nodes (9 floats), properties (list of floats: id, then the others in LIGGGHTS's order))] per element,
    in the file's order (the element ids say which triangle of the STL file)."""
    d = _fix_record(Path(path).read_bytes(), fix_id, style)
    n, size_elem, size_mesh = (int(v) for v in d[:3])
    out, m = [], 3
    for _ in range(n):
        count = int(d[m])
        if count != size_elem + 1:
            raise ValueError(f"element record of {count} values, expected {size_elem + 1}")
        rec = d[m + 1:m + count]
        out.append((rec[:9], rec[9:]))
        m += count
    if m + size_mesh != len(d):
        raise ValueError(f"restart record of {len(d)} values, expected {m + size_mesh}")
    return out


def wear_by_triangle(path, fix_id: str):
    """{STL triangle index: wear} of a fix mesh/surface/stress ... wear finnie (its elements carry id and wear)."""
    out = {}
    for nodes, props in mesh_elements(path, fix_id):
        if len(props) != 2:
            raise ValueError(f"element properties {props}: expected id and wear only")
        out[int(props[0])] = props[1]
    return out
