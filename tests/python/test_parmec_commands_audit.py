"""Seed commands and arguments the front end gained in the audit of issue 13 deliverable 4 (every command of
seed 000_06fddb409cce0c78 with its arguments, defaults and return values, or an error naming it): DEM output
intervals given as callbacks or TSERIES, DEM(prefix=), MESH face colours, ANALYTICAL(particle=), and bad
input (the cases are in test_parmec_front_end.py's BAD list, "audit" part)."""
import math

import pytest

from dembridge.parmec import ParmecError, run_script
from vtk_reader import read_pvd, read_vtu

PRE = ("m = MATERIAL(1000.0, 1e9, 0.25)\n"
       "p = SPHERE((0, 0, 0), 0.5, m, 1)\n"
       "q = SPHERE((2, 0, 0), 0.5, m, 1)\n"
       "ts = TSERIES([0, 0, 1, 1])\n")
CUBE = "nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]\n"


def test_interval_callbacks_and_tseries(tmp_path):
    """DEM(..., (files, history)) with a callback for the files and a TSERIES for the histories, evaluated at
    each step's time t_n (seed; Parmec's dem()): a constant TSERIES 0.05 samples exactly as the number 0.05
    does; files every 0.1 s before t = 0.45 and every 0.25 s after give frames near 0, 0.1, ..., 0.4, then
    0.4 + 0.25 = 0.65 and 0.9 (each at the first step at or past the due time, h = 0.01)."""
    body = ("GRAVITY(0.0, 0.0, -10.0)\nOUTPUT(mode='RB')\nT = HISTORY('TIME')\nZ = HISTORY('PZ', p)\n"
            "DEM(1.0, 0.01, {})\n")
    runs = {}
    for name, interval in (("calls", "(lambda t: 0.1 if t < 0.45 else 0.25, TSERIES([0, 0.05, 2, 0.05]))"),
                           ("numbers", "(0.1, 0.05)")):
        script = tmp_path / f"{name}.py"
        script.write_text(PRE + body.format(interval))
        runs[name] = run_script(str(script), [], workdir=str(tmp_path))
    assert runs["calls"]["T"] == runs["numbers"]["T"] and runs["calls"]["Z"] == runs["numbers"]["Z"]
    assert len(runs["calls"]["T"]) == 20
    times = [t for t, _ in read_pvd(str(tmp_path / "calls0rb.pvd"))]
    want = [0.0, 0.1, 0.2, 0.3, 0.4, 0.65, 0.9]
    assert len(times) == len(want) and all(0 <= t - w <= 0.01 + 1e-9 for t, w in zip(times, want)), times
    assert len(read_pvd(str(tmp_path / "numbers0rb.pvd"))) == 10


def test_prefix_names_the_files_and_cannot_change_later(tmp_path):
    script = tmp_path / "run.py"
    script.write_text(PRE + "OUTPUT(mode='RB')\nDEM(0.02, 0.01, prefix='first')\nDEM(0.02, 0.01, prefix='first')\n"
                            "DEM(0.02, 0.01, prefix='second')\n")
    with pytest.raises(ParmecError) as e:
        run_script(str(script), [], workdir=str(tmp_path))
    assert "DEM: argument 'prefix' = 'second'" in str(e.value)
    # in the script's folder; the initial state and the steps from t_n = 0.01 on (0.01, 0.02, 0.03)
    assert [round(t, 9) for t, _ in read_pvd(str(tmp_path / "first0rb.pvd"))] == [0.0, 0.01, 0.02, 0.03]
    # after RESET() a new prefix is fine
    script.write_text(PRE + "OUTPUT(mode='RB')\nDEM(0.02, 0.01, prefix='a')\nRESET()\n" + PRE +
                      "OUTPUT(mode='RB')\nDEM(0.02, 0.01, prefix='b')\n")
    run_script(str(script), [], workdir=str(tmp_path))
    assert (tmp_path / "b0rb.pvd").exists()


def test_mesh_face_colours_reach_the_output(tmp_path):
    """MESH(..., colors=[gcolor, 4, n1, n2, n3, n4, c, ...]): the top face (nodes 4 5 6 7) gets colour 5, the
    others the global colour 2; the MESH output colours its two triangles 5 and the other ten 2."""
    script = tmp_path / "faces.py"
    script.write_text("m = MATERIAL(1000.0, 1e9, 0.25)\n" + CUBE +
                      "b = MESH(nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, m], m, [2, 4, 7, 6, 5, 4, 5])\n"
                      "OUTPUT(mode='MESH')\nDEM(0.002, 0.001)\n")
    run_script(str(script), [], workdir=str(tmp_path))
    d = read_vtu(read_pvd(str(tmp_path / "faces0.pvd"))[-1][1])
    colours = [c[0] for c in d["cell"]["COLOR"]]
    top = [k for k, tri in enumerate(d["cells"]) if all(abs(d["points"][v][2] - 1.0) < 1e-12 for v in tri)]
    assert len(colours) == 12 and len(top) == 2
    assert all(colours[k] == 5 for k in top) and sorted(colours) == [2] * 10 + [5] * 2


def test_analytical_conversion_of_a_particle(tmp_path):
    """ANALYTICAL(particle=i) returns i; given mass and inertia replace the sphere's (a spin under a constant
    torque-free motion keeps ω; a spring's CRITICAL sees the new mass), the shape is kept for output, and the
    converted sphere makes no contact: dropped on an obstacle with a GRANULAR pairing it falls through."""
    script = tmp_path / "conv.py"
    script.write_text(
        "import math\nm = MATERIAL(1000.0, 1e9, 0.25)\n"
        "a = SPHERE((0, 0, 1.0), 0.5, m, 1)\n"
        "b = SPHERE((3, 0, 1.0), 0.5, m, 1)\n"
        "n = ANALYTICAL(particle=b, mass=2.0, inertia=[1.0, 2.0, 3.0, 0.0, 0.0, 0.0])\n"
        "OBSTACLE([(-9, -9, 0, 9, -9, 0, 9, 9, 0), (-9, -9, 0, 9, 9, 0, -9, 9, 0)], 2)\n"
        "GRANULAR(1, 2, 1e6, 0.5)\n"
        "SPRING(b, (3, 0, 1.0), -1, (3, 0, 5.0), [-1, -50, 1, 50], direction=(1, 0, 0))\n"
        "C = CRITICAL(perparticle=2)\n"
        "GRAVITY(0.0, 0.0, -10.0)\nOUTPUT(mode='SPH')\n"
        "ZA = HISTORY('PZ', a)\nZB = HISTORY('PZ', b)\nDEM(1.0, 1e-3, 0.1)\n")
    ns = run_script(str(script), [], workdir=str(tmp_path))
    assert ns["n"] == 1
    assert min(ns["ZA"]) > 0.45           # a rests on the obstacle
    assert ns["ZB"][-1] < -2.0            # b falls through it (x = 1 - g t^2/2 = -4 at t = 1)
    by = {c[1]: c for c in ns["C"]}
    assert abs(by[1][2] - math.sqrt(50 / 2.0)) < 1e-12 * 5   # the spring sees mass 2 (not the sphere's 523.6)
    d = read_vtu(read_pvd(str(tmp_path / "conv0sph.pvd"))[-1][1])
    assert [n[0] for n in d["point"]["NUMBER"]] == [0, 1]  # its shape is still drawn


def test_moving_obstacles_are_drawn_at_their_pose(tmp_path):
    """A plate rising at 0.5 m/s (linear callback) under a sphere resting on it, beside a static plate: group 0's
    MESH files draw both; the moving one at z = -1 + 0.5 t within one step's rise (0.5 h; its pose leads the
    particles by h/2), and at exactly the height of the sphere's contact point in the CD file of the same frame
    (both are fix parmec/granular's pose of that step)."""
    h = 1e-4
    script = tmp_path / "plate.py"
    script.write_text("m = MATERIAL(1000.0, 1e9, 0.25)\np = SPHERE((0, 0, -0.505), 0.5, m, 1)\n"
                      "OBSTACLE([(-5, -5, -3, 5, -5, -3, 5, 5, -3)], 2)\n"
                      "OBSTACLE([(-5, -5, -1, 5, -5, -1, 5, 5, -1), (-5, -5, -1, 5, 5, -1, -5, 5, -1)], 2, "
                      "point=(0, 0, -1), linear=lambda t: (0, 0, 0.5))\n"
                      "GRANULAR(1, 2, 1e6, 1.0)\nGRAVITY(0.0, 0.0, -10.0)\nOUTPUT(mode=['MESH', 'CD'])\n"
                      f"DEM(0.2, {h}, 0.05)\n")
    run_script(str(script), [], workdir=str(tmp_path))
    frames = read_pvd(str(tmp_path / "plate0.pvd"))
    cds = read_pvd(str(tmp_path / "plate0cd.pvd"))
    assert len(frames) == len(cds) == 4
    touched = 0
    for (t, path), (_, cpath) in zip(frames, cds):
        d = read_vtu(path)
        assert len(d["cells"]) == 3 and d["points"][0][2] == -3.0   # the static plate, then the moving one
        z = {p[2] for p in d["points"][3:]}
        assert len(z) == 1
        z = z.pop()
        assert abs(z - (-1 + 0.5 * t)) <= 0.5 * h * 1.0001, (t, z)
        c = read_vtu(cpath)
        if t > 0 and c["points"]:
            touched += 1
            assert abs(c["points"][0][2] - z) < 1e-12
    assert touched == 3
