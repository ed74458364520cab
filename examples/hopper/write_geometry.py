"""Writes the example's STL meshes: funnel.stl (an open conical hopper, outlet at z = 0) and
belt.stl (a flat conveyor below the outlet). Binary STL for the funnel (the plugin reads both;
LIGGGHTS only ASCII), ASCII for the belt."""
import math
import struct
import sys


def funnel(r_out=0.012, r_top=0.035, height=0.05, nseg=32):
    tris = []
    for k in range(nseg):
        a0, a1 = 2 * math.pi * k / nseg, 2 * math.pi * (k + 1) / nseg
        p0 = (r_out * math.cos(a0), r_out * math.sin(a0), 0.0)
        p1 = (r_out * math.cos(a1), r_out * math.sin(a1), 0.0)
        q0 = (r_top * math.cos(a0), r_top * math.sin(a0), height)
        q1 = (r_top * math.cos(a1), r_top * math.sin(a1), height)
        tris += [(p0, p1, q1), (p0, q1, q0)]
    return tris


def belt(z=-0.02, x0=-0.05, x1=0.25, half_width=0.04):
    a, b, c, d = (x0, -half_width, z), (x1, -half_width, z), (x1, half_width, z), (x0, half_width, z)
    return [(a, b, c), (a, c, d)]


def write_binary(path, tris):
    with open(path, "wb") as f:
        f.write(b"dembridge hopper funnel".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", 0.0, 0.0, 0.0))
            for p in t:
                f.write(struct.pack("<3f", *p))
            f.write(b"\0\0")


def write_ascii(path, tris, name):
    with open(path, "w") as f:
        f.write(f"solid {name}\n")
        for t in tris:
            f.write("  facet normal 0 0 0\n    outer loop\n")
            for p in t:
                f.write("      vertex %r %r %r\n" % p)
            f.write("    endloop\n  endfacet\n")
        f.write(f"endsolid {name}\n")


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    write_binary(f"{out}/funnel.stl", funnel())
    write_ascii(f"{out}/belt.stl", belt(), "belt")
