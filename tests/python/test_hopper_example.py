"""examples/hopper runs and does what it says (short version): the particles rest in the funnel
while the outlet is closed, then flow out onto the belt, and fix mesh/surface/stress reports a
downward force on the funnel of the order of the weight it carries."""
import os
import sys

from dembridge import ROOT

sys.path.insert(0, os.path.join(ROOT, "examples", "hopper"))
import run_hopper  # noqa: E402


def test_hopper_example_discharges_and_reports_the_funnel_force(tmp_path):
    nsettle, nrun = 9000, 4000
    rows = run_hopper.run(str(tmp_path), 1, nsettle, nrun)
    n0 = rows[0]["v_nin"]
    assert n0 > 1000
    at_open = next(r for r in rows if r["Step"] == nsettle)
    assert at_open["v_nin"] == n0                      # outlet closed: nothing leaves
    assert rows[-1]["v_nin"] < n0 - 20                 # outlet open: the funnel empties
    # the funnel carries a downward force of the order of the weight of its content
    late = [r for r in rows if r["Step"] > nsettle + 1000]
    fz = sum(r["v_fz"] for r in late) / len(late)
    weight = sum(r["v_nin"] for r in late) / len(late) * run_hopper.MASS * 9.81
    assert -1.5 * weight < fz < -0.3 * weight
    assert os.path.exists(tmp_path / "mesh_0.vtk") and os.path.exists(tmp_path / "mesh_12000.vtk")
    run_hopper.plot(rows, nsettle, str(tmp_path / "hopper.png"))
    assert os.path.getsize(tmp_path / "hopper.png") > 0
    # a run stopped right after the gate opened (shorter than the flow-rate window) still plots
    short = [r for r in rows if r["Step"] <= nsettle + 400]
    assert run_hopper.flow_rate(short, nsettle) == []
    assert run_hopper.summary(short, nsettle).endswith("run too short for a flow rate")
    assert "peak flow rate" in run_hopper.summary(rows, nsettle)
    run_hopper.plot(short, nsettle, str(tmp_path / "short.png"))
    assert os.path.getsize(tmp_path / "short.png") > 0
