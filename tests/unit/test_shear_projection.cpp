// The shear-history projection of tangential_history against its closed form: after the update the
// stored spring s' = s_t, the tangential part of s + vtr dt (s' . n = 0, |s'| not restored), in both
// forms; the 3.8 form (s.n) n and the 2.x form (s.del)/rsq del are the same maths and differ only in
// rounding, each bit for bit the expression LIGGGHTS of that version evaluates.
#include "contact_geometry.h"
#include "tangential_models.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dembridge::gran;

namespace {

// two spheres touching along an oblique normal, sliding slowly (vtr small), no spin
ContactGeometry oblique_contact()
{
  const double xi[3] = {0.0031, -0.0042, 0.0067}, xj[3] = {0, 0, 0};
  const double vi[3] = {0.013, 0.021, -0.007}, vj[3] = {0, 0, 0}, w0[3] = {0, 0, 0};
  const double del[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
  ContactGeometry g;
  touching_geometry(del, dot3(del, del), 0.005, 0.0045, vi, vj, w0, w0, true, g);
  return g;
}

struct Step {
  double shear[3], Ft[3];
};

// one updating step from a stored spring s0 with a normal component (the normal turned since it was stored)
Step update(const ContactGeometry &g, const double *s0, bool projection_2x, double Ft_max = 1e9)
{
  Step r;
  for (int k = 0; k < 3; ++k) r.shear[k] = s0[k];
  tangential_history(g, 1000.0, 0.5, Ft_max, 1e-6, true, projection_2x, r.shear, r.Ft);
  return r;
}

const double kS0[3] = {2.0e-6, -1.1e-6, 3.3e-6};

}  // namespace

TEST(ShearProjection, StoredSpringIsTheTangentialPartOfTheIncrementedSpring)
{
  const ContactGeometry g = oblique_contact();
  const double n[3] = {g.del[0] / std::sqrt(g.rsq), g.del[1] / std::sqrt(g.rsq), g.del[2] / std::sqrt(g.rsq)};
  double s[3], sn = 0.0;
  for (int k = 0; k < 3; ++k) s[k] = kS0[k] + g.vtr[k] * 1e-6;
  for (int k = 0; k < 3; ++k) sn += s[k] * n[k];
  ASSERT_GT(std::abs(sn), 0.3 * std::sqrt(dot3(s, s)));  // a real normal component to remove
  for (bool form2x : {false, true}) {
    const Step r = update(g, kS0, form2x);
    const double mag = std::sqrt(dot3(r.shear, r.shear));
    EXPECT_LT(std::abs(dot3(r.shear, n)), 1e-15 * mag) << "2x form " << form2x;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(r.shear[k], s[k] - sn * n[k], 1e-15 * mag) << "2x form " << form2x << " k " << k;
      // sticking: the spring of the projected shear plus the damping (spec §7.1)
      EXPECT_NEAR(r.Ft[k], -1000.0 * (s[k] - sn * n[k]) - 0.5 * g.vtr[k], 1e-12 * std::abs(r.Ft[k]) + 1e-18);
    }
    EXPECT_LT(mag, std::sqrt(dot3(s, s)) * 0.95);  // the magnitude is not restored
  }
}

TEST(ShearProjection, ThreeEightUsesTheUnitNormalTwoXTheCentreDifference)
{
  const ContactGeometry g = oblique_contact();
  double s[3];
  for (int k = 0; k < 3; ++k) s[k] = kS0[k] + g.vtr[k] * 1e-6;
  const double sn = s[0] * g.n[0] + s[1] * g.n[1] + s[2] * g.n[2];                          // 3.8
  const double rsht = (s[0] * g.del[0] + s[1] * g.del[1] + s[2] * g.del[2]) * (1.0 / g.rsq);  // 2.x
  const Step r38 = update(g, kS0, false), r2x = update(g, kS0, true);
  bool forms_differ = false;
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(r38.shear[k], s[k] - sn * g.n[k]) << k;
    EXPECT_EQ(r2x.shear[k], s[k] - rsht * g.del[k]) << k;
    forms_differ = forms_differ || r38.shear[k] != r2x.shear[k];
  }
  EXPECT_TRUE(forms_differ) << "pick a contact where the two roundings differ";
}

TEST(ShearProjection, SlidingTruncatesTheProjectedSpring)
{
  // Coulomb cap far below kt|s'|: |Ft| = Ft_max along -s', and the stored spring becomes Ft_max/kt
  const ContactGeometry g = oblique_contact();
  const Step free = update(g, kS0, false), r = update(g, kS0, false, 1e-4);
  const double mag = std::sqrt(dot3(free.shear, free.shear));
  ASSERT_GT(1000.0 * mag, 1e-4);
  EXPECT_NEAR(std::sqrt(dot3(r.Ft, r.Ft)), 1e-4, 1e-18);
  EXPECT_NEAR(std::sqrt(dot3(r.shear, r.shear)), 1e-7, 1e-21);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.shear[k] / 1e-7, free.shear[k] / mag, 1e-14);
}
