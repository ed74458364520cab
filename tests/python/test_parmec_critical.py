"""CRITICAL of the Parmec front end (spec parmec-springs §13) with the bodies' inertia tensors
(a MESH box 1 x 1 x 4, far from a sphere), with GRANULAR contact (the pairings a sphere can act in) and
between DEM calls,
against closed forms computed here with NumPy from the spec's formulas."""
import math
import sys

import numpy as np

from dembridge.parmec import run_script


# a box 1 x 1 x 4 of density 1000 (m = 4000, J = m/12 diag(1 + 16, 1 + 16, 1 + 1)); A: its corner (1, 1, 4)
# from the centre
BOX = ("m = MATERIAL(1000.0, 1e9, 0.25)\n"
       "nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 4, 1, 0, 4, 1, 1, 4, 0, 1, 4]\n"
       "b = MESH(nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, m], m, 1)\n")
BOX_MASS = 4000.0
BOX_J = np.diag([BOX_MASS / 12 * 17, BOX_MASS / 12 * 17, BOX_MASS / 12 * 2])
BOX_ARM = np.array([0.5, 0.5, 2.0])


def _run_box(tmp_path, body):
    script = tmp_path / "box.py"
    script.write_text(BOX + body)
    return run_script(str(script), [], workdir=str(tmp_path))


def _h(w, xi):
    return (2.0 / w) * (math.sqrt(1.0 + xi * xi) - xi)


def test_perparticle_uses_the_mesh_inertia_tensor(tmp_path):
    """A box 1 x 1 x 4 (density 1000: m = 4000, J = m/12 diag(1 + 16, 1 + 16, 1 + 1)) held by one spring of
    k = 1e6 along z at the corner point P = (1, 1, 4) (constant direction, no dashpot). Spec §13: translational
    w_t = sqrt(1 k / m); rotational w_r = sqrt(lambda_max(L^-1 K L^-T)), K = k (|A|^2 I - A A^T), A = P - X,
    J = L L^T; h = min(2/w_t, 2/w_r). The sphere inertia of the same trace would give another h."""
    ns = _run_box(tmp_path, "s = SPRING(b, (1, 1, 4), -1, (1, 1, 5), [-1, -1e6, 1, 1e6], direction=(0, 0, 1))\n"
                            "P = CRITICAL(perparticle=1)\nH = CRITICAL()\nS = CRITICAL(perspring=1)\n")
    mass, k, J, A = BOX_MASS, 1e6, BOX_J, BOX_ARM
    K = k * (A @ A * np.eye(3) - np.outer(A, A))
    Li = np.linalg.inv(np.linalg.cholesky(J))
    w_r = math.sqrt(max(np.linalg.eigvalsh(Li @ K @ Li.T)))
    w_t = math.sqrt(k / mass)
    want = min(2.0 / w_t, 2.0 / w_r)
    (h, i, w, xi), = ns["P"]
    assert i == 0 and xi == 0.0
    assert abs(h - want) <= 1e-12 * want and abs(w - max(w_t, w_r)) <= 1e-12 * max(w_t, w_r), (h, want)
    assert ns["H"] == h
    # the isotropic equivalent (trace/3) is far off: the test sees the tensor
    Ji = np.eye(3) * np.trace(J) / 3
    Li = np.linalg.inv(np.linalg.cholesky(Ji))
    iso = min(2.0 / w_t, 2.0 / math.sqrt(max(np.linalg.eigvalsh(Li @ K @ Li.T))))
    assert abs(iso - want) > 0.05 * want
    # per spring: m_s = EQM along z = 1/(1/m + (A x z) . J^-1 (A x z)); w = sqrt(k/m_s)
    c = np.cross(A, [0, 0, 1.0])
    m_s = 1.0 / (1.0 / mass + c @ np.linalg.inv(J) @ c)
    (hs, _, ws, _), = ns["S"]
    assert abs(ws - math.sqrt(k / m_s)) <= 1e-12 * ws


def test_perparticle_includes_the_contacts_a_sphere_can_make(tmp_path):
    """Spheres a (mass 1, colour 1, on a spring of k = 100 at its centre), b (mass 8, colour 2) and an obstacle
    (colour 9); GRANULAR(1, 2, k1, 0.5) and GRANULAR(2, 9, k2, 0.2). Per particle, the smaller of the spring
    estimate and of the contacts' (2/w)(sqrt(1 + xi^2) - xi), w = sqrt(k/m_i), xi = damper sqrt(m_eff/m_i):
    a: min(spring 2/sqrt(100), contact with b), b: min(contact with a, with the obstacle); before, a sphere
    without springs got the largest float."""
    k1, k2 = 1e4, 3e4
    script = tmp_path / "contact.py"
    script.write_text(
        "import math\n"
        "m = MATERIAL(3.0 / (4.0 * math.pi), 1e9, 0.25)\n"
        "a = SPHERE((0, 0, 5), 1.0, m, 1)\n"
        "b = SPHERE((0, 0, 9), 2.0, m, 2)\n"
        "OBSTACLE([(-5, -5, 0, 5, -5, 0, 5, 5, 0)], 9)\n"
        f"GRANULAR(1, 2, {k1}, 0.5)\nGRANULAR(2, 9, {k2}, 0.2)\n"
        "SPRING(a, (0, 0, 5), -1, (0, 0, 6), [-1, -100, 1, 100], direction=(0, 0, 1))\n"
        "P = CRITICAL(perparticle=2)\nH = CRITICAL()\n")
    ns = run_script(str(script), [], workdir=str(tmp_path))
    ma, mb = 1.0, 8.0
    meff = 1.0 / (1.0 / ma + 1.0 / mb)

    def contact(m, k, damper, me):
        w = math.sqrt(k / m)
        xi = damper * math.sqrt(me / m)
        return _h(w, xi), w, xi

    ha = min([(2.0 / 10.0, 10.0, 0.0), contact(ma, k1, 0.5, meff)])
    hb = min([contact(mb, k1, 0.5, meff), contact(mb, k2, 0.2, mb)])
    want = sorted([(ha[0], 0, ha[1], ha[2]), (hb[0], 1, hb[1], hb[2])])
    got = ns["P"]
    assert [g[1] for g in got] == [w[1] for w in want]
    for g, w in zip(got, want):
        assert all(abs(x - y) <= 1e-14 * abs(y) for x, y in zip((g[0], g[2], g[3]), (w[0], w[2], w[3]))), (g, w)
    assert ns["H"] == got[0][0] < sys.float_info.max


def test_critical_between_dem_calls_sees_the_current_state(tmp_path):
    """A follower spring at a corner of the box 1 x 1 x 4 (no force: zero stroke, no gravity). Before the first
    step its direction is unknown and the per-spring EQM is the largest point mass of the corner (spec §13,
    Q17 fixed: 1/lambda_min(M^-1)); after a DEM call CRITICAL reads the running model, where the direction is z:
    m_s = 1/(1/m + (A x z) . J^-1 (A x z)), as Parmec (which estimates from its current state)."""
    ns = _run_box(tmp_path, "SPRING(b, (1, 1, 4), -1, (1, 1, 5), [-1, -1e6, 1, 1e6])\n"
                            "S0 = CRITICAL(perspring=1)\nDEM(0.002, 0.001)\nS1 = CRITICAL(perspring=1)\n")
    mass, k, J, A = BOX_MASS, 1e6, BOX_J, BOX_ARM
    Ax = np.array([[0, -A[2], A[1]], [A[2], 0, -A[0]], [-A[1], A[0], 0]])
    Minv = np.eye(3) / mass + Ax @ np.linalg.inv(J) @ Ax.T
    c = np.cross(A, [0, 0, 1.0])
    before = math.sqrt(k * min(np.linalg.eigvalsh(Minv)))
    after = math.sqrt(k * (1.0 / mass + c @ np.linalg.inv(J) @ c))
    assert abs(ns["S0"][0][2] - before) <= 1e-12 * before
    assert abs(ns["S1"][0][2] - after) <= 1e-12 * after and abs(after - before) > 0.1 * before
