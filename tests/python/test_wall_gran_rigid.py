"""fix wall/gran with fix rigid (spec liggghts-walls §2: m* is the body's total mass). A vertical
dimer (two spheres of mass m, one rigid body of mass 2m) falls head-on onto a hooke wall without
gravity. The hooke damping is designed for m* so that the rebound speed is exactly e times the
impact speed for a mass m* on a linear spring-dashpot; with m* = 2m it is e = 0.7 (to the time-step
error); with the particle mass m it would be 0.78 (damping ratio smaller by sqrt 2)."""
import pytest

from dembridge import new_lammps


def rebound_ratio(rigid):
    lmp = new_lammps()
    try:
        for line in [
            "units si", "atom_style sphere", "boundary f f f", "newton off", "comm_modify vel yes",
            "region box block -0.05 0.05 -0.05 0.05 -0.01 0.1", "create_box 1 box",
            "create_atoms 1 single 0 0 0.0055 units box", "create_atoms 1 single 0 0 0.0155 units box",
            "set group all diameter 0.01 density 2500",
            "fix m1 all property/global youngsModulus peratomtype 5.e7",
            "fix m2 all property/global poissonsRatio peratomtype 0.3",
            "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
            "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
            "fix m5 all property/global characteristicVelocity scalar 1.0",
            "pair_style gran model hooke tangential history", "pair_coeff * *",
            "neigh_modify exclude type 1 1",
            "timestep 1e-7", "thermo_style custom step atoms",
            "fix w all wall/gran model hooke tangential history primitive type 1 zplane 0.0",
            "velocity all set 0 0 -0.5",
            "fix i all rigid single" if rigid else "fix i all nve/sphere",
            "run 20000",
        ]:
            lmp.command(line)
        v = lmp.numpy.extract_atom("v")
        return v[0][2] / -0.5, v[1][2] / -0.5
    finally:
        lmp.close()


def test_rigid_body_mass_is_the_wall_contact_mass():
    lo, hi = rebound_ratio(rigid=True)
    assert lo == pytest.approx(-0.7, abs=2e-3) and hi == pytest.approx(lo, abs=1e-12)


def test_without_rigid_each_sphere_uses_its_own_mass():
    lo, hi = rebound_ratio(rigid=False)
    assert lo == pytest.approx(-0.7, abs=2e-3) and hi == 1.0  # the upper sphere never touches
