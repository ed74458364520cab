"""OUTPUT modes 'SL', 'ST', 'JT' and 'CD' of the Parmec front end (issue 13, deliverable 4): VTK series of
linear springs, torsion springs, joints and contacts, parsed with the XML reader and checked against closed
forms of bodies at rest (a hanging spring, a pinned body, spheres stacked on an obstacle) and of a prescribed
spin, and against the HISTORY values of the same run; the subset semantics (file k holds what is attached
to the particles of the k-th OUTPUT subset, file 0 what is attached to the particles in no subset)."""
import math
import os

import pytest

from dembridge.parmec import ParmecError, run_script
from vtk_reader import read_pvd, read_vtu

# unit spheres of mass 1 (density 3/(4 pi)), g = 10
HEAD = ("import math\n"
        "m = MATERIAL(3.0 / (4.0 * math.pi), 1e9, 0.25)\n"
        "GRAVITY(0.0, 0.0, -10.0)\n")


def _last(tmp_path, stem):
    frames = read_pvd(str(tmp_path / f"{stem}.pvd"))
    return frames, read_vtu(frames[-1][1])


def test_spring_torsion_and_joint_series(tmp_path):
    script = tmp_path / "rig.py"
    script.write_text(HEAD +
        "a = SPHERE((0, 0, 0), 1.0, m, 1)\n"
        "s = SPRING(a, (0, 0, 0), -1, (0, 0, 2.0), [-1, -100.0, 1, 100.0], dashpot=1.0)\n"  # k = 100, critical
        "b = SPHERE((5, 0, 0), 1.0, m, 2)\n"
        "c = SPHERE((5, 0, -2.0), 1.0, m, 2)\n"
        "j0 = BALL_JOINT(b, (5, 0, 1.0))\n"                       # b pinned above its centre
        "j1 = BALL_JOINT(b, (5, 0, -1.0), c)\n"                   # c hangs from b
        "d = SPHERE((10, 0, 0), 1.0, m, 3)\n"
        "RESTRAIN(d, [1, 0, 0, 0, 1, 0, 0, 0, 1])\n"
        "PRESCRIBE(d, angular=(TSERIES(0.0), TSERIES(0.0), TSERIES(2.0)))\n"
        "t = TORSION_SPRING(d, -1, (0, 0, 1), (1, 0, 0), kyaw=[-10, -30, 10, 30], refpnt=(10.0, 0.5, 0.0))\n"
        "OUTPUT()\n"
        "OUTPUT(['NUMBER', 'JREAC'], subset=[c], mode=['JT', 'SL'])\n"
        "H = {e: HISTORY(e, s) for e in ('F', 'SF', 'STROKE', 'LENGTH', 'SS')}\n"
        "H['TIME'] = HISTORY('TIME')\n"
        "H['YAW'] = HISTORY('YAW', t)\n"
        "H['J0'] = HISTORY('JREAC_Z', j0)\n"
        "DEM(5.0, 0.001, 1.0)\n")
    ns = run_script(str(script), [], workdir=str(tmp_path))
    H, mg, k = ns["H"], 10.0, 100.0
    # the hanging spring (critically damped, 5 s = 50/omega): F = SF = m g, stroke m g / k, length 2 + m g / k
    frames, sl = _last(tmp_path, "rig0sl")
    assert len(frames) == 5 and frames[0][0] == 0.0   # initial state + t = 1, 2, 3, 4 (Parmec's output times)
    assert sl["types"] == [3] and sl["cells"] == [[0, 1]]
    cd = {n: v[0] for n, v in sl["cell"].items()}
    assert cd["NUMBER"] == [0] and cd["PAIR"] == [0, -1] and cd["SS"] == [-3.0] and cd["FF"] == [0.0]
    assert abs(cd["F"][0] - mg) < 1e-9 and abs(cd["SF"][0] - mg) < 1e-9
    assert abs(cd["DISPL"][0] - mg / k) < 1e-9 and abs(cd["LENGTH"][0] - (2.0 + mg / k)) < 1e-9
    assert max(abs(x - y) for x, y in zip(cd["ORIENT"], (0, 0, 1))) < 1e-12
    assert max(abs(x - y) for x, y in zip(sl["points"][0], (0, 0, -mg / k))) < 1e-9   # point1 on the sphere
    assert sl["points"][1] == [0.0, 0.0, 2.0]                                          # the spatial anchor
    row = H["TIME"].index(frames[-1][0])  # the frame holds the values of the HISTORY row of the same time
    assert [cd["F"][0], cd["SF"][0], cd["DISPL"][0], cd["LENGTH"][0], cd["SS"][0]] == \
        [H[e][row] for e in ("F", "SF", "STROKE", "LENGTH", "SS")]
    # before the first step: stroke and forces 0, the reference length
    first = {n: v[0] for n, v in read_vtu(frames[0][1])["cell"].items()}
    assert first["F"] == [0.0] and first["DISPL"] == [0.0] and first["LENGTH"] == [2.0]
    # joints: b pinned, c hanging from b, both at rest; JREAC is the joint's force on part1: the pin holds b
    # and c up (m_b g + m_c g), the lower joint pulls b down by c's weight; at the joint points
    frames, jt = _last(tmp_path, "rig0jt")
    assert jt["point"]["NUMBER"] == [[0], [1]]
    for got, want in zip(jt["point"]["JREAC"], ((0, 0, 2 * mg), (0, 0, -mg))):
        assert max(abs(x - y) for x, y in zip(got, want)) < 1e-9
    assert max(abs(x - y) for p, q in zip(jt["points"], ((5, 0, 1), (5, 0, -1))) for x, y in zip(p, q)) < 1e-12
    assert jt["point"]["JREAC"][0][2] == H["J0"][H["TIME"].index(frames[-1][0])]
    # torsion spring at a prescribed spin w = 2: yaw = TRQROT . ZDIR (the fix's value, = HISTORY YAW), TRQSPR
    # = 3 yaw z (table slope 3), XDIR = (cos theta, sin theta, 0) with theta = yaw within w h, at refpnt
    frames, st = _last(tmp_path, "rig0st")
    p = {n: v[0] for n, v in st["point"].items()}
    yaw = sum(x * y for x, y in zip(p["TRQROT"], p["ZDIR"]))
    tn = frames[-1][0]
    assert abs(yaw - H["YAW"][H["TIME"].index(tn)]) < 1e-14 * yaw and abs(yaw - 2.0 * tn) < 2.0 * 0.001 * 1.0001
    assert max(abs(x - y) for x, y in zip(p["TRQSPR"], (0, 0, 3 * yaw))) < 1e-12
    assert abs(p["XDIR"][0] - math.cos(yaw)) < 2e-3 and abs(p["XDIR"][1] - math.sin(yaw)) < 2e-3
    assert max(abs(x - y) for x, y in zip(p["YDIR"], (-p["XDIR"][1], p["XDIR"][0], 0))) < 1e-12
    r = math.hypot(st["points"][0][0] - 10.0, st["points"][0][1])  # refpnt turns with d about its centre
    assert abs(r - 0.5) < 1e-12 and abs(st["points"][0][2]) < 1e-12
    # subsets: file 1 (particle c) has the joint attached to c only, no springs (none attached to c), only the
    # requested arrays; file 0 (a, b, d) has both joints (each is attached to b)
    frames, jt1 = _last(tmp_path, "rig1jt")
    assert sorted(jt1["point"]) == ["JREAC", "NUMBER"] and jt1["point"]["NUMBER"] == [[1]]
    assert not os.path.exists(tmp_path / "rig1sl.pvd") and not os.path.exists(tmp_path / "rig1st.pvd")
    assert not os.path.exists(tmp_path / "rig1rb.pvd")  # mode=['JT', 'SL'] only


def test_contact_series_of_spheres_stacked_on_an_obstacle(tmp_path):
    k, r = 1e5, 1.0
    script = tmp_path / "stack.py"
    script.write_text(HEAD +
        "OBSTACLE([(-5, -5, 0, 5, -5, 0, 5, 5, 0), (-5, -5, 0, 5, 5, 0, -5, 5, 0)], 9)\n"
        "a = SPHERE((0, 0, 1.0), 1.0, m, 1)\n"
        "b = SPHERE((0, 0, 3.0), 1.0, m, 2)\n"
        f"GRANULAR(1, 9, {k}, 1.0)\n"
        f"GRANULAR(1, 2, {k}, 1.0)\n"
        "OUTPUT()\n"
        "OUTPUT(subset=[b], mode='CD')\n"
        "DEM(1.0, 1e-4, 0.25)\n")
    run_script(str(script), [], workdir=str(tmp_path))
    mg = 10.0
    frames, c0 = _last(tmp_path, "stack0cd")
    # Parmec's output times: the first step time t_n >= t_last + 0.25 (one step of 1e-4 past it)
    assert len(frames) == 4 and all(abs(t - (0.25 * n + (1e-4 if n else 0.0))) < 1e-9 for n, (t, _) in enumerate(frames))
    assert read_vtu(frames[0][1])["points"] == []   # no contact before the first step
    P = c0["point"]
    # the sphere on the obstacle (PAIR (0, -1)) carries both weights; the pair (0, 1): force on sphere 0
    at = {tuple(p): n for n, p in enumerate(P["PAIR"])}
    assert sorted(at) == [(0, -1), (0, 1)] and P["COLOR"][at[0, -1]] == [1, 9] and P["COLOR"][at[0, 1]] == [1, 2]
    for n, weight, sign in ((at[0, -1], 2 * mg, 1.0), (at[0, 1], mg, -1.0)):
        depth = weight / k
        assert abs(P["DISPL"][n][0] - depth) < 1e-9 * 1e-4 / depth
        assert max(abs(x - y) for x, y in zip(P["F"][n], (0, 0, sign * weight))) < 1e-6
        assert P["F"][n] == P["FN"][n] and max(abs(x) for x in P["FT"][n]) == 0.0 and P["FF"][n] == [0.0]
        assert abs(P["SF"][n][0] - weight) < 1e-6
        # the circle where the sphere meets the plane / the other sphere: pi (r^2 - (r - depth)^2) and
        # pi (r^2 - (r - depth/2)^2), to first order pi 2 r depth and pi r depth
        a = r - depth if n == at[0, -1] else r - depth / 2
        assert abs(P["AREA"][n][0] - math.pi * (r * r - a * a)) < 1e-9
    z = [c0["points"][at[0, -1]][2], c0["points"][at[0, 1]][2]]
    assert abs(z[0] - 0.0) < 1e-12 and abs(z[1] - (2.0 - 2 * mg / k - mg / (2 * k))) < 1e-6
    # the static obstacle is drawn in group 0's MESH file (owner -1, its colour), as Parmec draws obstacles
    _, mesh = _last(tmp_path, "stack0")
    assert mesh["cell"]["NUMBER"] == [[-1], [-1]] and mesh["cell"]["COLOR"] == [[9], [9]]
    assert mesh["points"][:3] == [[-5.0, -5.0, 0.0], [5.0, -5.0, 0.0], [5.0, 5.0, 0.0]]
    # subset b: only the contact involving b; its file 0 counterpart still lists it (a is in no subset)
    _, c1 = _last(tmp_path, "stack1cd")
    assert c1["point"]["PAIR"] == [[0, 1]]
    assert sorted(c1["point"]) == ["AREA", "COLOR", "DISPL", "F", "FF", "FN", "FT", "PAIR", "SF"]


def test_output_modes_and_entities_are_checked(tmp_path):
    script = tmp_path / "bad.py"
    for call, words in (("OUTPUT(mode='XX')", ("OUTPUT", "mode", "'XX'")),
                        ("OUTPUT(mode=['SL', 7])", ("OUTPUT", "mode", "7")),
                        ("OUTPUT(['NUMBER', 'SPEED'])", ("OUTPUT", "entities", "SPEED")),
                        ("OUTPUT(format='MED')", ("OUTPUT", "format", "MED"))):
        script.write_text(HEAD + "a = SPHERE((0, 0, 0), 1.0, m, 1)\n" + call + "\n")
        with pytest.raises(ParmecError) as e:
            run_script(str(script), [], workdir=str(tmp_path))
        assert all(w in str(e.value) for w in words), (call, str(e.value))
    # the seed's other name of the torsion mode
    script.write_text(HEAD + "a = SPHERE((0, 0, 0), 1.0, m, 1)\n"
                      "TORSION_SPRING(a, -1, (0, 0, 1), (1, 0, 0), kyaw=[-1, -1, 1, 1])\n"
                      "OUTPUT(mode='TS')\nDEM(0.002, 0.001)\n")
    run_script(str(script), [], workdir=str(tmp_path))
    assert read_vtu(read_pvd(str(tmp_path / "bad0st.pvd"))[-1][1])["point"]["NUMBER"] == [[0]]
