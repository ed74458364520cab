"""Writes meshes/funnel.stl: a square funnel (four inclined plates, open at the bottom) as ASCII STL.
Run once; the STL is kept beside the deck."""
import os

TOP, BOTTOM, Z_TOP, Z_BOTTOM = 0.05, 0.012, 0.07, 0.025  # half widths (m) and heights (m)


def corners(h, z):
    return [(-h, -h, z), (h, -h, z), (h, h, z), (-h, h, z)]


def facet(a, b, c):
    return "  facet normal 0 0 0\n    outer loop\n" + "".join(
        f"      vertex {v[0]:g} {v[1]:g} {v[2]:g}\n" for v in (a, b, c)) + "    endloop\n  endfacet\n"


def main():
    top, bottom = corners(TOP, Z_TOP), corners(BOTTOM, Z_BOTTOM)
    text = "solid funnel\n"
    for k in range(4):
        a, b, c, d = bottom[k], bottom[(k + 1) % 4], top[(k + 1) % 4], top[k]
        text += facet(a, b, c) + facet(a, c, d)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "meshes", "funnel.stl")
    with open(path, "w") as fh:
        fh.write(text + "endsolid funnel\n")


if __name__ == "__main__":
    main()
