"""Rolling, cohesion and viscous sub-models through LAMMPS (issue 4): the fixed LIGGGHTS quirks
and the closed-form limits that the oracle cases do not cover."""
import math

import numpy as np
import pytest

from dembridge import new_lammps

R, RHO, Y, NU = 0.005, 2500.0, 5e7, 0.3


def two_spheres(pair_style, gap, v=0.0, extra=()):
    """Two R = 5 mm spheres on the x axis with centre distance 2R + gap, approaching at ±v/2."""
    lmp = new_lammps()
    for line in ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f", "newton off",
                 "comm_modify vel yes", "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05", "create_box 1 box",
                 f"create_atoms 1 single {-(R + gap / 2)!r} 0 0 units box", f"create_atoms 1 single {R + gap / 2!r} 0 0 units box",
                 f"set group all diameter {2 * R!r} density {RHO!r}", "velocity all set 0 0 0",
                 f"set atom 1 vx {v / 2!r}", f"set atom 2 vx {-v / 2!r}",
                 f"fix m1 all property/global youngsModulus peratomtype {Y!r}",
                 f"fix m2 all property/global poissonsRatio peratomtype {NU!r}",
                 "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
                 "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
                 "fix m5 all property/global characteristicVelocity scalar 1.0",
                 "fix v1 all property/global FluidViscosity peratomtypepair 1 0.1",
                 "fix v2 all property/global MaximumRestitution peratomtypepair 1 0.9",
                 "fix v3 all property/global CriticalStokes peratomtypepair 1 10",
                 "fix r1 all property/global coefficientRollingFriction peratomtypepair 1 0.1",
                 "fix r2 all property/global coefficientRollingViscousDamping peratomtypepair 1 0.3",
                 "fix k1 all property/global kn peratomtypepair 1 2e4", "fix k2 all property/global kt peratomtypepair 1 1e4",
                 "fix k3 all property/global gamman peratomtypepair 1 3000", "fix k4 all property/global gammat peratomtypepair 1 1500",
                 *extra, f"pair_style {pair_style}", "pair_coeff * *", "neighbor 0.001 bin", "neigh_modify delay 0",
                 "timestep 1e-7", "fix integr all nve/sphere"]:
        lmp.command(line)
    return lmp


def gathered(lmp, name):
    return np.array(lmp.gather_atoms(name, 1, 3)).reshape(-1, 3)


def hooke_kn():
    m = 4.0 / 3.0 * math.pi * R ** 3 * RHO
    meff, reff = m / 2, R / 2
    yeff = 1.0 / (2 * (1 - NU * NU) / Y)
    return 16.0 / 15.0 * math.sqrt(reff) * yeff * (15.0 * meff / (16.0 * math.sqrt(reff) * yeff)) ** 0.2


@pytest.mark.parametrize("style", ["gran/hooke/history viscous stokes", "gran model hooke tangential history viscous on"])
def test_viscous_at_rest_gives_finite_spring_force(style):
    """LIGGGHTS 3.8 gives NaN here (St = 0, inf/inf); the limit ln e → −∞ is finite, and at vn = 0
    the damping term vanishes, so the force is the spring kn δ of spec §5.1."""
    delta = 1e-5
    lmp = two_spheres(style, -delta)
    lmp.command("run 0")
    f = gathered(lmp, "f")
    lmp.close()
    assert np.all(np.isfinite(f))
    assert f[1, 0] == pytest.approx(hooke_kn() * delta, rel=1e-9)
    assert f[0, 0] == pytest.approx(-f[1, 0], rel=1e-15)


def test_viscous_restitution_never_exceeds_maximum():
    """Head-on at 0.5 m/s in a fluid: the rebound must be slower than e_max v (issue 4: never above
    MaximumRestitution), while 3.8's signed Stokes number accelerates the separating pair."""
    lmp = two_spheres("gran/hooke/history viscous stokes", 1e-6, v=0.5)
    lmp.command("run 20000")
    v = gathered(lmp, "v")
    lmp.close()
    vrel_out = v[1, 0] - v[0, 0]
    assert vrel_out > 0.0, "the spheres must rebound"
    assert vrel_out < 0.9 * 0.5


def test_epsd_with_stiffness_history_style_runs():
    """2.3.8 dereferenced a NULL table here (epsd with gran/*/history/stiffness); it must give a
    rolling torque opposing the relative rotation."""
    lmp = two_spheres("gran/hooke/history/stiffness rolling_friction epsd", -1e-5)
    lmp.command("set atom 1 omega 0 0 10")  # opposite spins: no slip at the contact, pure relative rolling
    lmp.command("set atom 2 omega 0 0 -10")
    lmp.command("run 10")
    t = gathered(lmp, "torque")
    lmp.close()
    assert np.all(np.isfinite(t))
    assert t[0, 2] < 0.0 < t[1, 2]
    assert t[0, 2] == pytest.approx(-t[1, 2], rel=1e-12)


def test_hooke_epsd2_is_refused_not_silently_cdt():
    with pytest.raises(Exception, match="needs per-contact history"):
        two_spheres("gran/hooke rolling_friction epsd2", -1e-5)


@pytest.mark.parametrize("model", ["sjkr", "sjkr2"])
def test_cohesion_force_is_energy_density_times_area(model):
    """At rest (no damping), two overlapping spheres: Fn = kn δ − k A with the sjkr lens area
    π a² or the sjkr2 area 2π(2R*)δ (spec §6)."""
    delta, k = 1e-5, 3.0e5
    lmp = two_spheres(f"gran/hooke/history cohesion {model}", -delta,
                      extra=[f"fix c1 all property/global cohesionEnergyDensity peratomtypepair 1 {k!r}"])
    lmp.command("run 0")
    f = gathered(lmp, "f")
    lmp.close()
    r = 2 * R - delta
    a2 = R * R - (r / 2) ** 2  # radius² of the intersection circle of two equal spheres
    area = math.pi * a2 if model == "sjkr" else 2 * math.pi * R * delta
    assert f[1, 0] == pytest.approx(hooke_kn() * delta - k * area, rel=1e-9)


def test_run_pre_no_continues_the_history_bitwise():
    """`run 10` + `run 5 pre no` must equal `run 15`: no setup, so the contact history in
    neighbour-list order carries over unchanged."""
    def final(runs):
        lmp = two_spheres("gran/hertz/history", -2e-5, v=0.0)
        lmp.command("set atom 1 vy 0.3")
        for r in runs:
            lmp.command(r)
        out = np.concatenate([gathered(lmp, q) for q in ("x", "v", "omega", "f", "torque")])
        lmp.close()
        return out
    assert np.array_equal(final(["run 15"]), final(["run 10", "run 5 pre no post no"]))
