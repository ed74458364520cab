"""`shear x V` on a primitive plane (a conveyor, spec liggghts-walls §3): a sphere resting on a belt
moving at V is dragged by friction until it rolls without slipping on the belt. The angular momentum
about the contact point is conserved while it slides, so it ends at v = 2/7 V with ω = -5/2 v/R
about y (solid sphere, closed form); checked to 0.5 % (the tangential spring and the damping of the
contact are not in the closed form)."""
import pytest

from dembridge import new_lammps


def test_sphere_on_moving_plane_ends_at_two_sevenths_of_the_belt_speed():
    R, V = 0.005, 0.1
    lmp = new_lammps()
    try:
        for line in [
            "units si", "atom_style sphere", "boundary f f f", "newton off", "comm_modify vel yes",
            "region box block -0.05 0.05 -0.05 0.05 -0.01 0.05", "create_box 1 box",
            f"create_atoms 1 single 0 0 {R} units box", f"set group all diameter {2 * R} density 2500",
            "fix m1 all property/global youngsModulus peratomtype 5.e7",
            "fix m2 all property/global poissonsRatio peratomtype 0.3",
            "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5",
            "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
            "fix m5 all property/global characteristicVelocity scalar 1.0",
            "pair_style gran model hertz tangential history", "pair_coeff * *",
            "timestep 1e-6",
            f"fix belt all wall/gran model hertz tangential history primitive type 1 zplane 0.0 shear x {V}",
            "fix i all nve/sphere", "fix g all gravity 9.81 vector 0 0 -1",
            "run 30000",
        ]:
            lmp.command(line)
        v = lmp.numpy.extract_atom("v")[0].copy()  # a copy: the view dies with lmp.close()
        w = lmp.numpy.extract_atom("omega")[0].copy()
    finally:
        lmp.close()
    assert v[0] == pytest.approx(2.0 / 7.0 * V, rel=5e-3)
    assert w[1] == pytest.approx(-2.5 * v[0] / R, rel=5e-3)
    assert abs(v[1]) < 1e-12
