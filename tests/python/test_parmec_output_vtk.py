"""OUTPUT(format='VTK') of the Parmec front end (issue 13, deliverable 4): the .pvd/.vtu files ParaView opens,
parsed with a small VTK XML reader: frame times, point counts, positions against the closed form of Parmec's
leap-frog for a free fall (x at the row of t_n is x_{n+3/2} = x0 - g h^2 (n+1)(n+2)/2), rotation columns,
mesh triangles at x + Λ(P - X), and a subset series of its own."""
from dembridge.parmec import run_script
from vtk_reader import read_pvd, read_vtu

CUBE = ("nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]\n"
        "def moved(dx): return [c + (dx if k % 3 == 0 else 0) for k, c in enumerate(nodes)]\n")


def test_vtk_series_of_a_falling_cube_and_a_subset(tmp_path):
    script = tmp_path / "fall.py"
    script.write_text(
        "m = MATERIAL(1000.0, 1e9, 0.25)\n" + CUBE +
        "a = MESH(nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, m], m, 1)\n"
        "b = MESH(moved(3.0), [8, 0, 1, 2, 3, 4, 5, 6, 7, m], m, 2)\n"
        "c = MESH(moved(6.0), [8, 0, 1, 2, 3, 4, 5, 6, 7, m], m, 3)\n"
        "VELOCITY(b, angular=(0, 0, 2.0))\n"
        "GRAVITY(0.0, 0.0, -10.0)\n"
        "OUTPUT()\n"
        "OUTPUT(['NUMBER', 'LINVEL'], subset=[c])\n"
        "H = {'TIME': HISTORY('TIME'), 'PZ': HISTORY('PZ', a), 'bPX': HISTORY('PX', b)}\n"
        "DEM(0.05, 0.001, (0.01, 0.001))\n"
        "DEM(0.02, 0.001, (0.01, 0.001))\n")
    ns = run_script(str(script), [], workdir=str(tmp_path))
    h, g, z0 = 0.001, 10.0, 0.5
    frames = read_pvd(str(tmp_path / "fall0rb.pvd"))
    # Parmec writes the initial state and then every 0.01 s over both DEM calls: 0, 0.01, ..., 0.06 (the
    # last step of the second call is at t = 0.069999..., before 0.07)
    assert len(frames) == 7, frames
    for k, (t, path) in enumerate(frames):
        n = round(t / h)
        assert abs(t - n * h) < 1e-12 and abs(t - 0.01 * k) < 1e-9
        d = read_vtu(path)
        assert len(d["points"]) == 2 and d["types"] == [1, 1] and d["cells"] == [[0], [1]]
        assert d["point"]["NUMBER"] == [[0], [1]] and d["point"]["COLOR"] == [[1], [2]]
        za = d["points"][0][2]
        expect = z0 if k == 0 else z0 - g * h * h * (n + 1) * (n + 2) / 2
        assert abs(za - expect) < 1e-12, (t, za, expect)
        assert abs(d["point"]["DISPL"][0][2] - (expect - z0)) < 1e-12
        # the spinning cube: ORIENT1/2 columns orthonormal, ANGVEL (0, 0, 2), ORIENT = rows of Λ
        c1, c2 = d["point"]["ORIENT1"][1], d["point"]["ORIENT2"][1]
        assert abs(sum(x * x for x in c1) - 1) < 1e-14 and abs(sum(x * y for x, y in zip(c1, c2))) < 1e-14
        L = d["point"]["ORIENT"][1]
        assert [L[0], L[3], L[6]] == c1
        assert max(abs(a - b) for a, b in zip(d["point"]["ANGVEL"][1], (0.0, 0.0, 2.0))) < 1e-15
        if k:  # the same values as the HISTORY rows of that time
            row = ns["H"]["TIME"].index(min(ns["H"]["TIME"], key=lambda x: abs(x - t)))
            assert d["points"][0][2] == ns["H"]["PZ"][row] and d["points"][1][0] == ns["H"]["bPX"][row]
        # mesh file: 12 triangles per cube at x + Λ(P - X), outward
        m = read_vtu(path.replace("fall0rb_", "fall0_"))
        assert len(m["cells"]) == 24 and set(m["types"]) == {5} and len(m["points"]) == 16
        assert m["cell"]["NUMBER"] == [[0]] * 12 + [[1]] * 12
        x, X = d["points"][1], (3.5, 0.5, 0.5)
        rows = [L[0:3], L[3:6], L[6:9]]
        for node, P in enumerate([(3, 0, 0), (4, 1, 1)]):
            q = [x[r] + sum(rows[r][c] * (P[c] - X[c]) for c in range(3)) for r in range(3)]
            got = m["points"][8 + (0 if node == 0 else 6)]
            assert max(abs(a - b) for a, b in zip(q, got)) < 1e-14
        for tri in m["cells"][:12]:
            p0, p1, p2 = (m["points"][v] for v in tri)
            u, w = [p1[i] - p0[i] for i in range(3)], [p2[i] - p0[i] for i in range(3)]
            nrm = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
            cen = [sum(p[i] for p in (p0, p1, p2)) / 3 - d["points"][0][i] for i in range(3)]
            assert sum(a * b for a, b in zip(nrm, cen)) > 0  # normal points away from the centre
    # the subset series: only cube c (which file 0 leaves out, as Parmec's files 0 hold the particles in no
    # subset), only the requested fields (+ RADIUS for glyphs)
    sub = read_pvd(str(tmp_path / "fall1rb.pvd"))
    assert len(sub) == 7
    d = read_vtu(sub[-1][1])
    assert len(d["points"]) == 1 and sorted(d["point"]) == ["LINVEL", "NUMBER", "RADIUS"]
    assert d["point"]["NUMBER"] == [[2]]
    assert len(read_vtu(read_pvd(str(tmp_path / "fall1.pvd"))[-1][1])["cells"]) == 12
