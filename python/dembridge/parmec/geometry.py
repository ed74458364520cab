"""Mass properties of Parmec MESH particles (mass, centre, inertia tensor about the centre) from the
element nodes and densities: every element is split into tetrahedra from its centroid over its
(triangulated) faces, and the tetrahedra's exact moments are summed. Small 3x3 helpers for the rest."""
import math

# faces of Parmec's elements by node count (outward for the node orders of the seed's figure)
_FACES = {
    4: [(0, 2, 1), (0, 1, 3), (1, 2, 3), (2, 0, 3)],
    5: [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
    6: [(0, 2, 1), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)],
    8: [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)],
}


def _tet_moments(a, b, c, d):
    """(volume, first moments, second moments Σ x_i x_j over the tetrahedron) with signed volume."""
    det = (b[0] - a[0]) * ((c[1] - a[1]) * (d[2] - a[2]) - (c[2] - a[2]) * (d[1] - a[1])) \
        - (b[1] - a[1]) * ((c[0] - a[0]) * (d[2] - a[2]) - (c[2] - a[2]) * (d[0] - a[0])) \
        + (b[2] - a[2]) * ((c[0] - a[0]) * (d[1] - a[1]) - (c[1] - a[1]) * (d[0] - a[0]))
    vol = det / 6.0
    pts = (a, b, c, d)
    first = [vol * sum(p[i] for p in pts) / 4.0 for i in range(3)]
    second = [[0.0] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(3):
            s = sum(p[i] * p[j] for p in pts) + sum(p[i] for p in pts) * sum(p[j] for p in pts)
            second[i][j] = vol * s / 20.0
    return vol, first, second


def mesh_mass_properties(nodes, elements, densities):
    """nodes: flat [x0,y0,z0,...]; elements: Parmec list [n, i1..in, mat, ...]; densities: material -> rho.
    Returns (mass, centre[3], inertia 3x3 about the centre, volume)."""
    pts = [tuple(nodes[3 * k:3 * k + 3]) for k in range(len(nodes) // 3)]
    mass, mom, sec, volume = 0.0, [0.0] * 3, [[0.0] * 3 for _ in range(3)], 0.0
    k = 0
    while k < len(elements):
        n = int(elements[k])
        ids = [int(e) for e in elements[k + 1:k + 1 + n]]
        rho = densities[int(elements[k + 1 + n])]
        k += n + 2
        cen = [sum(pts[i][c] for i in ids) / n for c in range(3)]
        for face in _FACES[n]:
            f = [pts[ids[i]] for i in face]
            for t in range(1, len(f) - 1):  # fan triangulation
                vol, first, second = _tet_moments(cen, f[0], f[t], f[t + 1])
                volume += abs(vol)
                mass += rho * vol
                for i in range(3):
                    mom[i] += rho * first[i]
                    for j in range(3):
                        sec[i][j] += rho * second[i][j]
    if mass < 0:  # inward face order: flip every sign consistently
        mass, mom, sec = -mass, [-m for m in mom], [[-s for s in r] for r in sec]
    centre = [m / mass for m in mom]
    # inertia about the centre: J = tr(S) I − S with S the second moments about the centre
    S = [[sec[i][j] - mass * centre[i] * centre[j] for j in range(3)] for i in range(3)]
    tr = S[0][0] + S[1][1] + S[2][2]
    J = [[(tr if i == j else 0.0) - S[i][j] for j in range(3)] for i in range(3)]
    return mass, centre, J, volume


def matvec(M, v):
    return [sum(M[i][k] * v[k] for k in range(3)) for i in range(3)]


def mattvec(M, v):
    return [sum(M[k][i] * v[k] for k in range(3)) for i in range(3)]


def inv3(M):
    a, b, c = M[0]
    d, e, f = M[1]
    g, h, i = M[2]
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    if det == 0:
        raise ZeroDivisionError("singular 3x3 matrix")
    return [[(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
            [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
            [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def quat_from_matrix(L):
    """(w, x, y, z) of a rotation matrix (rows), for LAMMPS 'set atom ... quat'."""
    tr = L[0][0] + L[1][1] + L[2][2]
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        return [0.25 * s, (L[2][1] - L[1][2]) / s, (L[0][2] - L[2][0]) / s, (L[1][0] - L[0][1]) / s]
    i = max(range(3), key=lambda k: L[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + L[i][i] - L[j][j] - L[k][k])
    q = [0.0] * 4
    q[0] = (L[k][j] - L[j][k]) / s
    q[1 + i] = 0.25 * s
    q[1 + j] = (L[j][i] + L[i][j]) / s
    q[1 + k] = (L[k][i] + L[i][k]) / s
    return q
