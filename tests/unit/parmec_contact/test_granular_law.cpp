// Parmec's GRANULAR law (spec parmec-springs §11) against closed forms.
#include "granular_law.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

using namespace dembridge::parmec_contact;

namespace {

Pairing pairing(double k, double z, double mus, double mud, double kskn)
{
  Pairing p;
  p.spring = k;
  p.damper = z;
  p.mu_static = mus;
  p.mu_dynamic = mud;
  p.kskn = kskn;
  return p;
}

}  // namespace

TEST(GranularLaw, NormalSpringDamperIsKdPlusCriticalRatioTimesVn)
{
  const double k = 1e5, z = 0.3, m = 2.0, d = 1e-3, vn = 0.7;
  Vec3 s{0, 0, 0};
  const ContactOutput out = granular_force(pairing(k, z, 0, 0, 0.5), {{0, 0, 1}, {0, 0, vn}, d, m, 1e-4}, s, true);
  const double en = z * 2.0 * std::sqrt(k * m);
  EXPECT_DOUBLE_EQ(out.kn, k);
  EXPECT_DOUBLE_EQ(out.en, en);
  EXPECT_DOUBLE_EQ(out.fn, k * d + en * vn);
  EXPECT_DOUBLE_EQ(out.f[2], k * d + en * vn);
  EXPECT_EQ(out.f[0], 0.0);
  EXPECT_EQ(out.f[1], 0.0);
}

TEST(GranularLaw, EffectiveMassOfTwoSpheres)
{
  EXPECT_DOUBLE_EQ(effective_mass(2.0, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(effective_mass(1.0, 3.0), 0.75);
}

TEST(GranularLaw, TangentialSpringAndDashpotScaleWithKskn)
{
  // below the Coulomb limit: F_t = kskn k s + kskn e_n v_t with s = h v_t
  const double k = 1e4, z = 0.5, m = 1.0, h = 1e-3, kskn = 0.25, vt = 0.2;
  Vec3 s{0.01, 0, 0};
  const ContactOutput out = granular_force(pairing(k, z, 10.0, 10.0, kskn), {{0, 0, 1}, {vt, 0, 0}, 1e-2, m, h}, s, true);
  const double en = z * 2.0 * std::sqrt(k * m);
  EXPECT_DOUBLE_EQ(s[0], 0.01 + h * vt);
  EXPECT_DOUBLE_EQ(out.f[0], kskn * k * s[0] + kskn * en * vt);
  EXPECT_DOUBLE_EQ(out.f[2], k * 1e-2);
}

TEST(GranularLaw, CoulombLimitScalesToDynamicFrictionAndKeepsTheSpring)
{
  const double k = 1e4, d = 1e-3, h = 1e-3, mus = 0.5, mud = 0.3;
  Vec3 s{0.05, 0.05, 0};  // far beyond the static limit
  const ContactOutput out = granular_force(pairing(k, 0.0, mus, mud, 0.5), {{0, 0, 1}, {0, 0, 0}, d, 1.0, h}, s, true);
  const double fn = k * d;
  EXPECT_NEAR(std::hypot(out.f[0], out.f[1]), mud * fn, 1e-12 * fn);
  EXPECT_NEAR(out.f[0] / out.f[1], 1.0, 1e-15);  // direction of the spring kept
  EXPECT_EQ(s[0], 0.05);                          // Parmec does not rescale the tangential spring
  EXPECT_EQ(s[1], 0.05);
}

TEST(GranularLaw, NoFrictionNoTangentialForce)
{
  Vec3 s{0, 0, 0};
  const ContactOutput out = granular_force(pairing(1e4, 0.2, 0, 0, 0.5), {{1, 0, 0}, {0, 3, 0}, 1e-3, 1.0, 1e-3}, s, true);
  EXPECT_EQ(out.f[1], 0.0);
  EXPECT_DOUBLE_EQ(out.f[0], out.fn);
}

TEST(GranularLaw, SeparatingDampedContactWithoutTangentialForceIsFinite)
{
  // F_n < 0 (damping while separating) and F_t = 0: Parmec divides 0/0 here; guarded
  Vec3 s{0, 0, 0};
  const ContactOutput out = granular_force(pairing(1e4, 1.0, 0.5, 0.5, 0.5), {{0, 0, 1}, {0, 0, -10}, 1e-6, 1.0, 1e-3}, s, true);
  EXPECT_LT(out.fn, 0.0);
  EXPECT_TRUE(std::isfinite(out.f[0]) && std::isfinite(out.f[2]));
}

TEST(GranularLaw, TrialEvaluationKeepsTheState)
{
  Vec3 s{0.1, 0.2, 0.3};
  granular_force(pairing(1e4, 0.2, 1, 1, 0.5), {{0, 0, 1}, {1, 1, 0}, 1e-3, 1.0, 1e-3}, s, false);
  EXPECT_EQ(s[0], 0.1);
  EXPECT_EQ(s[1], 0.2);
  EXPECT_EQ(s[2], 0.3);
}

TEST(GranularLaw, RestitutionOfTheDamperRatio)
{
  EXPECT_DOUBLE_EQ(restitution_of_damper(0.0), 1.0);
  EXPECT_NEAR(restitution_of_damper(0.1), std::exp(-M_PI * 0.1 / std::sqrt(0.99)), 1e-15);
  EXPECT_EQ(restitution_of_damper(1.0), 0.0);
}

// The discrete bounce of a point mass under Parmec's leap-frog (forces at x_{n+1/2}, v_n) converges to
// the closed-form restitution as h -> 0.
TEST(GranularLaw, LeapFrogBounceApproachesTheClosedFormRestitution)
{
  const double k = 1e6, m = 1.0, z = 0.2, v0 = -1.0;
  const double period = M_PI / std::sqrt(k / m * (1 - z * z));
  double err_prev = 0.0;
  for (int level = 0; level < 3; ++level) {
    const double h = period / (200.0 * (1 << level));
    double x = 0.5 * h * v0, v = v0;  // overlap x < 0 means contact; Parmec's unforced half drift first
    bool touched = false;
    Vec3 s{0, 0, 0};
    for (int n = 0; n < 1000000; ++n) {
      double f = 0.0;
      if (x < 0.0) {
        touched = true;
        f = granular_force(pairing(k, z, 0, 0, 0.5), {{0, 0, 1}, {0, 0, -v}, -x, m, h}, s, true).f[2];
      } else if (touched) {
        break;
      }
      v += h * f / m;
      x += h * v;
    }
    const double err = std::fabs(v / -v0 - restitution_of_damper(z));
    EXPECT_LT(err, 0.02) << "h = T/" << 200 * (1 << level);
    if (level > 0) {
      EXPECT_LT(err, 0.6 * err_prev);  // O(h): halves with h
    }
    std::printf("restitution error at h = T/%d: %.3e\n", 200 * (1 << level), err);
    err_prev = err;
  }
}

TEST(PairingTable, DefaultsSymmetryAndWildcard)
{
  PairingTable t;
  EXPECT_EQ(t.find(3, 4).spring, 0.0);  // the seed's defaults
  EXPECT_EQ(t.find(3, 4).damper, 1.0);
  EXPECT_EQ(t.find(3, 4).kskn, 0.5);
  EXPECT_FALSE(t.any_contact());
  t.set(4, 3, pairing(100, 0.1, 0.2, 0.2, 0.5));
  EXPECT_EQ(t.find(3, 4).spring, 100);
  EXPECT_EQ(t.find(4, 3).spring, 100);
  EXPECT_EQ(t.find(3, 3).spring, 0.0);
  t.set(0, 0, pairing(7, 0.1, 0, 0, 0.5));  // redefines the default of unspecified pairs
  EXPECT_EQ(t.find(3, 3).spring, 7);
  EXPECT_EQ(t.find(1, 9).spring, 7);
  EXPECT_EQ(t.find(3, 4).spring, 100);
  EXPECT_TRUE(t.any_contact());
}

TEST(PairingTable, BadInputIsRefused)
{
  PairingTable t;
  EXPECT_THROW(t.set(0, 5, pairing(1, 1, 0, 0, 0.5)), std::invalid_argument);
  EXPECT_THROW(t.set(-1, 5, pairing(1, 1, 0, 0, 0.5)), std::invalid_argument);
  EXPECT_THROW(t.set(1, 2, pairing(-1, 1, 0, 0, 0.5)), std::invalid_argument);
  EXPECT_THROW(t.set(1, 2, pairing(1, -1, 0, 0, 0.5)), std::invalid_argument);
  EXPECT_THROW(t.set(1, 2, pairing(1, 1, -0.1, 0, 0.5)), std::invalid_argument);
  EXPECT_THROW(t.set(1, 2, pairing(1, 1, 0, 0, -0.5)), std::invalid_argument);
  EXPECT_THROW(t.set(1, 2, pairing(NAN, 1, 0, 0, 0.5)), std::invalid_argument);
}
