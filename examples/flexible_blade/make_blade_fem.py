"""Writes blade.fem: MBDyn's modal FEM data file (the `from file` argument of its modal joint) of
a cantilevered blade, 0.1 m x 0.03 m in the x-y plane, clamped along x = 0, as 11 x 4 FEM nodes
0.01 m apart (the nodes of in.blade's blade atoms), with two modes of transverse (z) deflection:
  mode 1, bending:  phi_z = s^2 (3 - s) / 2         (s = x / L; the static deflection shape, 1 at the tip)
  mode 2, torsion:  phi_z = s * y / (W / 2)          (the blade's edges at the tip move by +-1)
The blade's mass (BLADE_MASS) is lumped equally on its nodes; the modal mass is sum_v m_v phi^2,
the stiffness gives the natural frequencies FREQ, the damping the ratio ZETA of critical.
It also writes blade.stl, the blade's surface as 60 triangles whose vertices are the FEM nodes (the
surface of `python run_blade.py --surface mesh`).
Usage: python make_blade_fem.py [blade.fem [blade.stl]]"""
import math
import sys

L, W, NX, NY = 0.1, 0.03, 11, 4
BLADE_MASS = 0.05          # kg
FREQ = (10.0, 30.0)        # Hz
ZETA = 0.02


def nodes():
    """(label, x, y) in label order: x fastest within a row of constant y."""
    out = []
    for j in range(NY):
        for i in range(NX):
            out.append((1 + i + NX * j, round(i * L / (NX - 1), 12), round(-W / 2 + j * W / (NY - 1), 12)))
    return out


def shapes(x, y):
    s = x / L
    return (s * s * (3 - s) / 2, s * y / (W / 2))


def write(path):
    ns = nodes()
    m_node = BLADE_MASS / len(ns)
    phi = [[shapes(x, y)[m] for (_, x, y) in ns] for m in range(2)]
    mass = [sum(m_node * p * p for p in phi[m]) for m in range(2)]
    stiff = [mass[m] * (2 * math.pi * FREQ[m]) ** 2 for m in range(2)]
    damp = [2 * ZETA * mass[m] * 2 * math.pi * FREQ[m] for m in range(2)]
    r = repr
    lines = ["** MBDyn MODAL DATA FILE: cantilevered blade of examples/flexible_blade (make_blade_fem.py)",
             "** RECORD GROUP 1, HEADER", "**   REVISION,  NODE,  NORMAL, ATTACHMENT, CONSTRAINT, REJECTED MODES.",
             f"      REV0        {len(ns)}        2        0           0           0", "**",
             "** RECORD GROUP 2, FINITE ELEMENT NODE LIST", " ".join(str(n[0]) for n in ns), "**",
             "** RECORD GROUP 3, INITIAL MODAL DISPLACEMENTS", "0. 0.", "**",
             "** RECORD GROUP 4, INITIAL MODAL VELOCITIES", "0. 0.", "**"]
    for g, c in ((5, 1), (6, 2)):
        lines += [f"** RECORD GROUP {g}, NODAL {'XY'[c - 1]} COORDINATES"] + [r(n[c]) for n in ns] + ["**"]
    lines += ["** RECORD GROUP 7, NODAL Z COORDINATES"] + ["0."] * len(ns) + ["**"]
    lines += ["** RECORD GROUP 8, NON-ORTHOGONALIZED MODE SHAPES"]
    for m in range(2):
        lines += [f"**    NORMAL MODE SHAPE #  {m + 1}"] + [f"0. 0. {r(p)} 0. 0. 0." for p in phi[m]]
    lines += ["**"]
    for g, name, d in ((9, "MODAL MASS", mass), (10, "MODAL STIFFNESS", stiff)):
        lines += [f"** RECORD GROUP {g}, {name} MATRIX.  COLUMN-MAJOR FORM", f"{r(d[0])} 0.", f"0. {r(d[1])}", "**"]
    lines += ["** RECORD GROUP 11, DIAGONAL OF LUMPED MASS MATRIX"]
    lines += [f"{r(m_node)} {r(m_node)} {r(m_node)} 0. 0. 0." for _ in ns] + ["**"]
    lines += ["** RECORD GROUP 13, MODAL DAMPING MATRIX.  COLUMN-MAJOR FORM", f"{r(damp[0])} 0.", f"0. {r(damp[1])}",
              "**", "** END OF FILE"]
    open(path, "w").write("\n".join(lines) + "\n")


def write_stl(path):
    """Two triangles per cell of the node grid, counter-clockwise seen from +z."""
    xy = {(i, j): (round(i * L / (NX - 1), 12), round(-W / 2 + j * W / (NY - 1), 12)) for i in range(NX) for j in range(NY)}
    out = ["solid blade"]
    for j in range(NY - 1):
        for i in range(NX - 1):
            a, b, c, d = xy[i, j], xy[i + 1, j], xy[i + 1, j + 1], xy[i, j + 1]
            for tri in ((a, b, c), (a, c, d)):
                out += ["  facet normal 0 0 1", "    outer loop"]
                out += [f"      vertex {v[0]!r} {v[1]!r} 0.0" for v in tri] + ["    endloop", "  endfacet"]
    open(path, "w").write("\n".join(out + ["endsolid blade"]) + "\n")


if __name__ == "__main__":
    write(sys.argv[1] if len(sys.argv) > 1 else "blade.fem")
    write_stl(sys.argv[2] if len(sys.argv) > 2 else "blade.stl")
