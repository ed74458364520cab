// Finnie's wear model (walls/mesh/finnie_wear) against its closed form.
#include "finnie_wear.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dembridge::mesh;

TEST(FinnieWear, AngleFactorBranches)
{
  const double g = 10.0 * M_PI / 180.0;  // shallow: 3 sin < cos
  EXPECT_DOUBLE_EQ(finnie_angle_factor(std::sin(g), std::cos(g)), std::sin(2 * g) - 3 * std::sin(g) * std::sin(g));
  const double h = 40.0 * M_PI / 180.0;  // steep: 3 sin > cos
  EXPECT_DOUBLE_EQ(finnie_angle_factor(std::sin(h), std::cos(h)), 0.33333 * std::cos(h) * std::cos(h));
  EXPECT_EQ(finnie_angle_factor(1.0, 0.0), 0.0);  // head-on
}

TEST(FinnieWear, IncrementOfOneContact)
{
  const Vec3 n{0, 0, 1}, c{0, 0, -0.004};
  const Vec3 v{0.6, 0.8, -0.2};  // |v_t| = 1, tan(gamma) = 0.2: shallow branch
  const double speed = std::sqrt(1.04), s = 0.2 / speed, co = 1.0 / speed;
  const double expect = 2 * 1.5 * speed * 7.0 * (2 * s * co - 3 * s * s) * 1e-5 / 2e-4;
  EXPECT_NEAR(finnie_wear_increment(c, v, n, 1.5, 7.0, 1e-5, 2e-4), expect, 1e-14 * expect);
  EXPECT_EQ(finnie_wear_increment(c, Vec3{0.3, 0.4, 0.2}, n, 1.5, 7.0, 1e-5, 2e-4), 0.0);  // moving away
  EXPECT_EQ(finnie_wear_increment(c, Vec3{1e-8, 0, 0}, n, 1.5, 7.0, 1e-5, 2e-4), 0.0);     // below 1e-7
}
