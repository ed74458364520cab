"""examples/flexible_blade runs (the test peer playing blade.mbd's clamped modal joint, 1500 steps)
and its coupling is exact where it can be checked independently of fix mbdyn, at every dumped step k:
- the blade atoms sit at X + sum_m q_m phi_m of the modal coordinates MBDyn (the peer) sent at step k,
  those of its step k-1 (MBDyn 1.7.3 sends the modal joint's last converged states; recorded);
- the generalized forces the peer received at step k are the virtual work of the blade atoms'
  forces in the dump, p_m = sum_v phi_m(v) . f_v, with phi read from blade.fem here;
- the blade's total force balances the particles' contact forces: sum_blade f = -(sum_particles f - weight).
With --surface mesh (the blade's surface the STL mesh blade.stl): every vertex of the dumped mesh sits
at X + sum q phi, and the particles bend the blade.
The blade's modal dynamics are the test peer's (M q'' + C q' + K q = p, crank nicolson); the
recorded MBDyn modal runs are of a free body, so they do not check these dynamics."""
import importlib.util
import math
import os
import shutil
import tempfile

import pytest

from dembridge import plugin_path, read_dump_atoms
from test_fix_mbdyn import PEER

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "flexible_blade")
STEPS, EVERY = 1500, 100

pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")


def load_example():
    spec = importlib.util.spec_from_file_location("run_blade", os.path.join(EXAMPLE, "run_blade.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def read_dump(path):
    """The one frame of a dump file as a list of atoms (dict column -> value)."""
    (_, cols), = read_dump_atoms(path)
    return [{c: float(cols[c][i]) for c in cols} for i in range(len(cols["id"]))]


def test_blade_example_loads_are_the_virtual_work_of_the_contact_forces():
    blade = load_example()
    fem = blade.read_fem(os.path.join(EXAMPLE, "blade.fem"))
    out = tempfile.mkdtemp(prefix="blade", dir="/tmp")
    blade.run(plugin_path(), PEER, STEPS, EVERY, out)
    rows = blade.read_modes(out)
    assert len(rows) == STEPS + 1  # t0 and every step: the peer completed (exit 0 checked by run)
    blade.snapshot(out, "atoms")  # the picture the README names
    assert os.path.getsize(os.path.join(out, "snapshot.png")) > 10000
    worst_x = worst_p = worst_f = 0.0
    pmax = max(max(abs(r[7]), abs(r[8])) for r in rows)
    contact_steps = 0
    for k in range(EVERY, STEPS + 1, EVERY):
        atoms = read_dump(os.path.join(out, f"blade.{k}.dump"))
        bl = [a for a in atoms if a["type"] == 2]
        st = [a for a in atoms if a["type"] == 1]
        q = rows[k - 1][1:3]
        p = [0.0, 0.0]
        for a in bl:  # the FEM node of each blade atom: the nearest rest position in the x-y plane
            v = min(range(len(fem["xyz"])), key=lambda i: (fem["xyz"][i][0] - a["x"]) ** 2 + (fem["xyz"][i][1] - a["y"]) ** 2)
            for c, name in enumerate("xyz"):
                want = fem["xyz"][v][c] + sum(q[m] * fem["phi"][m][v][c] for m in range(2))
                worst_x = max(worst_x, abs(a[name] - want))
            for m in range(2):
                p[m] += sum(fem["phi"][m][v][c] * a["f" + "xyz"[c]] for c in range(3))
        worst_p = max(worst_p, max(abs(p[m] - rows[k][7 + m]) for m in range(2)) / pmax)
        fb = [sum(a["f" + c] for a in bl) for c in "xyz"]
        weight = sum(2500 * 4 / 3 * math.pi * a["radius"] ** 3 * 9.81 for a in st)
        fs = [sum(a["f" + c] for a in st) for c in "xyz"]
        fs[2] += weight
        scale = max(1e-300, max(abs(v) for v in fb))
        worst_f = max(worst_f, max(abs(fb[c] + fs[c]) for c in range(3)) / scale)
        contact_steps += scale > 1e-6
    print(f"blade: positions {worst_x:.2e} m, p {worst_p:.2e} of max |p| = {pmax:.3g} N, force balance "
          f"{worst_f:.2e}; {contact_steps} of {STEPS // EVERY} dumped steps with contacts; q1 at the end {rows[-1][1]:.3e}")
    assert contact_steps >= 8                     # the particles load the blade
    assert rows[-1][1] < -5e-4                    # and bend it down (the tip deflection q1, m)
    assert worst_x <= 1e-15
    assert worst_p <= 1e-12
    assert worst_f <= 1e-12
    shutil.rmtree(out, ignore_errors=True)


def test_blade_example_mesh_surface_deforms_with_the_modes():
    blade = load_example()
    fem = blade.read_fem(os.path.join(EXAMPLE, "blade.fem"))
    out = tempfile.mkdtemp(prefix="blade", dir="/tmp")
    blade.run(plugin_path(), PEER, STEPS, 500, out, surface="mesh")
    rows = blade.read_modes(out)
    assert len(rows) == STEPS + 1
    blade.snapshot(out, "mesh")
    assert os.path.getsize(os.path.join(out, "snapshot.png")) > 10000
    worst = 0.0
    for k in range(500, STEPS + 1, 500):
        q = rows[k - 1][1:3]
        verts = [[float(x) for x in l.split()[1:4]] for l in open(os.path.join(out, f"surface_{k}.stl"))
                 if l.strip().startswith("vertex")]
        assert len(verts) == 180 and os.path.getsize(os.path.join(out, f"surface_{k}.vtk")) > 0
        for v in verts:
            n = min(range(len(fem["xyz"])), key=lambda i: (fem["xyz"][i][0] - v[0]) ** 2 + (fem["xyz"][i][1] - v[1]) ** 2)
            want = [fem["xyz"][n][c] + sum(q[m] * fem["phi"][m][n][c] for m in range(2)) for c in range(3)]
            worst = max(worst, max(abs(v[c] - want[c]) for c in range(3)))
    print(f"blade mesh: vertices {worst:.2e} m from X + sum q phi; q1 at the end {rows[-1][1]:.3e}, "
          f"min p1 {min(r[7] for r in rows):.3g} N")
    assert worst <= 1e-15
    assert rows[-1][1] < -5e-4 and min(r[7] for r in rows) < -0.05  # the particles load and bend the blade
    shutil.rmtree(out, ignore_errors=True)
