// gran/hooke is a linear spring-dashpot with constant kn, γn per pair: a head-on collision must
// rebound with exactly the coefficient of restitution e and last t_c = π / ω_d (closed form,
// spec granular-models §5.1), independent of how many MPI ranks share the two atoms.
#include "lammps_fixture.h"

#include <cmath>

namespace {

struct HeadOn {
  double e, v0, R1, R2, rho;
};

}  // namespace

class HookeHeadOn : public LammpsWithPlugin {
 protected:
  void setup_pair(const HeadOn &c, double dt)
  {
    ok("units si");
    ok("atom_style sphere");
    ok("atom_modify map array");
    ok("boundary f f f");
    ok("newton off");
    ok("comm_modify vel yes");
    ok("region box block -0.05 0.05 -0.05 0.05 -0.05 0.05");
    ok("create_box 1 box");
    const double gap = 1e-5;
    ok("create_atoms 1 single " + num(-(c.R1 + gap)) + " 0 0 units box");
    ok("create_atoms 1 single " + num(c.R2 + gap) + " 0 0 units box");
    ok("set atom 1 diameter " + num(2 * c.R1) + " density " + num(c.rho));
    ok("set atom 2 diameter " + num(2 * c.R2) + " density " + num(c.rho));
    ok("velocity all set 0 0 0");
    ok("set atom 1 vx " + num(c.v0 / 2));
    ok("set atom 2 vx " + num(-c.v0 / 2));
    ok("fix m1 all property/global youngsModulus peratomtype 5.e7");
    ok("fix m2 all property/global poissonsRatio peratomtype 0.3");
    ok("fix m3 all property/global coefficientRestitution peratomtypepair 1 " + num(c.e));
    ok("fix m4 all property/global coefficientFriction peratomtypepair 1 0.3");
    ok("fix m5 all property/global characteristicVelocity scalar 1.0");
    ok("pair_style gran/hooke");
    ok("pair_coeff * *");
    ok("neighbor 0.001 bin");
    ok("neigh_modify delay 0");
    ok("timestep " + num(dt));
    ok("fix integr all nve/sphere");
  }
};

TEST_F(HookeHeadOn, ReboundsWithCoefficientOfRestitution)
{
  const HeadOn c{0.7, 0.4, 0.005, 0.004, 2500.0};
  const double dt = 2e-8;
  setup_pair(c, dt);
  // run until well after separation
  ok("run 60000 post no");
  const auto v = gather3("v");
  const double vrel_after = v[0] - v[3];  // atom 1 minus atom 2, along x
  EXPECT_LT(vrel_after, 0.0) << "spheres must have rebounded";
  EXPECT_NEAR(-vrel_after / c.v0, c.e, 1e-4);  // O(dt) integration error: measured 1.5e-5
  // momentum is conserved exactly up to round-off
  const double m1 = 4.0 / 3.0 * M_PI * std::pow(c.R1, 3) * c.rho, m2 = 4.0 / 3.0 * M_PI * std::pow(c.R2, 3) * c.rho;
  EXPECT_NEAR(m1 * v[0] + m2 * v[3], m1 * c.v0 / 2 - m2 * c.v0 / 2, 1e-15);
}

TEST_F(HookeHeadOn, ContactDurationIsHalfDampedPeriod)
{
  const HeadOn c{0.5, 0.4, 0.005, 0.005, 2500.0};
  const double dt = 1e-7;
  setup_pair(c, dt);
  // count the steps that end with a non-zero contact force on atom 1
  int touching = 0;
  ok("run 0 post no");
  for (int steps = 0; steps < 20000; ++steps) {
    ok("run 1 pre no post no");
    const double fx = gather3("f")[0];
    if (fx != 0.0) ++touching;
    else if (touching > 0) break;
  }
  ASSERT_GT(touching, 0);
  // closed form: kn from characteristicVelocity (spec §5.1), γn from e
  const double m = 4.0 / 3.0 * M_PI * std::pow(c.R1, 3) * c.rho, meff = m / 2, Reff = c.R1 / 2;
  const double nu = 0.3, Y = 5e7, Yeff = 1.0 / (2 * (1 - nu * nu) / Y), V = 1.0;
  const double kn = 16.0 / 15.0 * std::sqrt(Reff) * Yeff * std::pow(15.0 * meff * V * V / (16.0 * std::sqrt(Reff) * Yeff), 0.2);
  const double lne = std::log(c.e);
  const double gn = std::sqrt(4 * meff * kn / (1 + std::pow(M_PI / lne, 2)));
  const double wd = std::sqrt(kn / meff - std::pow(gn / (2 * meff), 2));
  const double tc = M_PI / wd;
  EXPECT_NEAR(touching * dt, tc, 2 * dt) << "t_c closed form " << tc;
}
