"""Mass properties of Parmec MESH particles (mass, centre, inertia tensor about the centre) from the
element nodes and densities, computed in Parmec's operation order (its MESH_Char, spec parmec-springs §1):
every element face is fanned into triangles, each triangle with the mesh's first node spans a simplex,
and the simplex integrals of 1, x, x x^T are summed (bulk elements first, then surface elements, each
list in reverse input order), so that the mass, centre and inertia agree with Parmec's bitwise; the
integration is exact, only the rounding is Parmec's. Small 3x3 helpers for the rest."""
import math

# faces of Parmec's elements by node count (1-based, outward for the node orders of the seed's figure)
_FACES = {
    4: [(1, 3, 2), (1, 2, 4), (2, 3, 4), (3, 1, 4)],
    5: [(1, 4, 3, 2), (1, 2, 5), (2, 3, 5), (3, 4, 5), (4, 1, 5)],
    6: [(1, 3, 2), (4, 5, 6), (1, 2, 5, 4), (2, 3, 6, 5), (3, 1, 4, 6)],
    8: [(1, 4, 3, 2), (1, 2, 6, 5), (2, 3, 7, 6), (3, 4, 8, 7), (1, 5, 8, 4), (5, 6, 7, 8)],
}
_NEIGHS = {4: 4, 5: 5, 6: 5, 8: 6}


def _simplex_det(a, b, c, d):
    """Six times the signed volume of (a, b, c, d), expanded as Parmec's simplex_J."""
    q = [b[0] - a[0], c[0] - a[0], d[0] - a[0], b[1] - a[1], c[1] - a[1], d[1] - a[1],
         b[2] - a[2], c[2] - a[2], d[2] - a[2]]
    return (q[0] * q[4] * q[8] + q[3] * q[7] * q[2] + q[6] * q[1] * q[5]
            - q[6] * q[4] * q[2] - q[0] * q[7] * q[5] - q[3] * q[1] * q[8])


def _simplex_second(J, pts, i, j):
    """∫ x_i x_j over the simplex scaled by J (= rho * det): J/120 Σ_p Σ_r (1 + δ_pr) p_i r_j."""
    s = None
    for p in pts:
        for r in pts:
            t = (2. * p[i]) * p[j] if p is r else p[i] * r[j]
            s = t if s is None else s + t
    return (J / 120.) * s


def _elements(elements):
    """[(node ids, material)] of Parmec's element list [n, i1..in, mat, ...]."""
    out, k = [], 0
    while k < len(elements):
        n = int(elements[k])
        out.append(([int(e) for e in elements[k + 1:k + 1 + n]], int(elements[k + 1 + n])))
        k += n + 2
    return out


def mesh_mass_properties(nodes, elements, densities):
    """nodes: flat [x0,y0,z0,...]; elements: Parmec list [n, i1..in, mat, ...]; densities: material -> rho.
    Returns (mass, centre[3], inertia 3x3 about the centre, volume)."""
    pts = [tuple(float(c) for c in nodes[3 * k:3 * k + 3]) for k in range(len(nodes) // 3)]
    elems = _elements(elements)
    # face adjacency decides bulk (every face shared) or surface elements
    count = {}
    for ids, _ in elems:
        for f in _FACES[len(ids)]:
            key = tuple(sorted(ids[v - 1] for v in f))
            count[key] = count.get(key, 0) + 1
    bulk, surface = [], []
    for ids, mat in elems:
        shared = sum(1 for f in _FACES[len(ids)] if count[tuple(sorted(ids[v - 1] for v in f))] > 1)
        (bulk if shared >= _NEIGHS[len(ids)] else surface).append((ids, mat))
    zero = pts[min(i for ids, _ in elems for i in ids)]
    me = sx = sy = sz = 0.0
    eu = [0.0] * 9
    volume = 0.0
    for ids, mat in list(reversed(bulk)) + list(reversed(surface)):
        rho = densities[mat]
        for f in _FACES[len(ids)]:
            a = pts[ids[f[0] - 1]]
            for j in range(1, len(f) - 1):
                b, c = pts[ids[f[j] - 1]], pts[ids[f[j + 1] - 1]]
                det = _simplex_det(zero, a, b, c)
                J = rho * det
                simplex = (zero, a, b, c)
                volume += det / 6.
                me += J / 6.
                sx += (J / 24.) * (((zero[0] + a[0]) + b[0]) + c[0])
                sy += (J / 24.) * (((zero[1] + a[1]) + b[1]) + c[1])
                sz += (J / 24.) * (((zero[2] + a[2]) + b[2]) + c[2])
                for k, (p, q) in ((0, (0, 0)), (3, (0, 1)), (4, (1, 1)), (6, (0, 2)), (7, (1, 2)), (8, (2, 2))):
                    eu[k] += _simplex_second(J, simplex, p, q)
    if me < 0:  # inward face order: the same mesh turned inside out
        me, sx, sy, sz, eu, volume = -me, -sx, -sy, -sz, [-e for e in eu], -volume
    c = [sx / me, sy / me, sz / me]
    eu[0] -= (2 * sx - c[0] * me) * c[0]
    eu[4] -= (2 * sy - c[1] * me) * c[1]
    eu[8] -= (2 * sz - c[2] * me) * c[2]
    eu[3] -= c[0] * sy + c[1] * sx - c[0] * c[1] * me
    eu[6] -= c[0] * sz + c[2] * sx - c[0] * c[2] * me
    eu[7] -= c[1] * sz + c[2] * sy - c[1] * c[2] * me
    eu[1], eu[2], eu[5] = eu[3], eu[6], eu[7]
    trace = (eu[0] + eu[4]) + eu[8]
    # inertia = trace I - euler (Parmec's column-major 9 values; symmetric)
    J9 = [(trace if k in (0, 4, 8) else 0.0 * trace) - eu[k] for k in range(9)]
    return me, c, [[J9[0], J9[3], J9[6]], [J9[1], J9[4], J9[7]], [J9[2], J9[5], J9[8]]], volume


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
