// The math layer's rotations against closed forms: a quarter turn about z, Rodrigues' matrix of a
// rotation vector, and the round trips quaternion -> matrix -> quaternion and matrix -> axis, angle.
#include "math/quaternion.h"
#include "math/rotation.h"
#include "math/vec3.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dembridge::math;

namespace {

constexpr double kTol = 1e-15;

Mat9 matrix_of(const BodyRotation &r)
{
  return {r.m[0][0], r.m[0][1], r.m[0][2], r.m[1][0], r.m[1][1], r.m[1][2], r.m[2][0], r.m[2][1], r.m[2][2]};
}

// R(θ) about the unit axis n = (1, 2, 2)/3, written out (Rodrigues): cI + s[n]x + (1 - c) n nᵀ
Mat9 rodrigues_closed_form(double th)
{
  const double n[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3}, c = std::cos(th), s = std::sin(th), t = 1 - c;
  return {c + t * n[0] * n[0],        t * n[0] * n[1] - s * n[2], t * n[0] * n[2] + s * n[1],
          t * n[1] * n[0] + s * n[2], c + t * n[1] * n[1],        t * n[1] * n[2] - s * n[0],
          t * n[2] * n[0] - s * n[1], t * n[2] * n[1] + s * n[0], c + t * n[2] * n[2]};
}

void expect_near(const Mat9 &a, const Mat9 &b, double tol)
{
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(a[k], b[k], tol) << "element " << k;
}

}  // namespace

TEST(MathRotations, QuarterTurnAboutZ)
{
  const Quat q = axis_angle_quat({0, 0, 1}, kPi / 2);
  const Vec3 r = quat_rotate({1, 0, 0}, q);
  EXPECT_NEAR(r[0], 0.0, kTol);
  EXPECT_NEAR(r[1], 1.0, kTol);
  EXPECT_NEAR(r[2], 0.0, kTol);
  const Vec3 b = BodyRotation::of(q.data()).apply({1, 0, 0});
  EXPECT_NEAR(b[0], 0.0, kTol);
  EXPECT_NEAR(b[1], 1.0, kTol);
  const Vec3 back = BodyRotation::of(q.data()).apply_t({0, 1, 0});
  EXPECT_NEAR(back[0], 1.0, kTol);
  EXPECT_NEAR(back[1], 0.0, kTol);
}

TEST(MathRotations, BothQuaternionMatricesAreRodrigues)
{
  const double th = 0.7;
  const Quat q = axis_angle_quat({1.0 / 3, 2.0 / 3, 2.0 / 3}, th);
  expect_near(matrix_of(BodyRotation::of(q.data())), rodrigues_closed_form(th), 4 * kTol);
  expect_near(matrix_of_unit_quat(q), rodrigues_closed_form(th), 4 * kTol);
  expect_near(rotation_of_vector({th / 3, 2 * th / 3, 2 * th / 3}), rodrigues_closed_form(th), 4 * kTol);
}

TEST(MathRotations, QuaternionOfMatrixRoundTrip)
{
  for (double th : {0.3, 2.0, 3.1}) {  // the trace > 0 branch and the largest-diagonal branches
    const Quat q = axis_angle_quat({1.0 / 3, 2.0 / 3, 2.0 / 3}, th);
    const Quat p = quat_of_matrix(rodrigues_closed_form(th));
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(p[k], q[k], 4 * kTol) << "theta " << th << " component " << k;
  }
}

TEST(MathRotations, AxisAngleOfRodrigues)
{
  Vec3 axis{};
  EXPECT_NEAR(axis_angle(rodrigues_closed_form(1.2), axis), 1.2, 4 * kTol);
  EXPECT_NEAR(axis[0], 1.0 / 3, 4 * kTol);
  EXPECT_NEAR(axis[1], 2.0 / 3, 4 * kTol);
  EXPECT_NEAR(axis[2], 2.0 / 3, 4 * kTol);
  EXPECT_NEAR(axis_angle(rodrigues_closed_form(kPi), axis), kPi, 4 * kTol);  // the angle-pi branch
  EXPECT_NEAR(axis[0], 1.0 / 3, 1e-8);
  EXPECT_EQ(axis_angle({1, 0, 0, 0, 1, 0, 0, 0, 1}, axis), 0.0);
}

TEST(MathRotations, SlerpHalfwayIsHalfTheAngle)
{
  const Mat9 I{1, 0, 0, 0, 1, 0, 0, 0, 1};
  expect_near(slerp(I, rodrigues_closed_form(1.0), 0.5), rodrigues_closed_form(0.5), 4 * kTol);
  EXPECT_EQ(slerp(I, rodrigues_closed_form(1.0), 0.0), I);
  EXPECT_EQ(slerp(I, rodrigues_closed_form(1.0), 1.0), rodrigues_closed_form(1.0));
}

TEST(MathRotations, ProductsOfRotations)
{
  // R(a) R(b) = R(a + b) about one axis; Rᵀ undoes R
  expect_near(mat_mul(rodrigues_closed_form(0.4), rodrigues_closed_form(0.5)), rodrigues_closed_form(0.9), 4 * kTol);
  const Mat9 R = rodrigues_closed_form(0.4);
  const double v[3] = {0.3, -1.2, 2.5};
  const Vec3 w = mat_vec(R, v);
  const Vec3 u = mat_t_vec(R, w.data());
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(u[k], v[k], 4 * kTol);
  const Vec3 c = cross(Vec3{1, 0, 0}, Vec3{0, 1, 0});
  EXPECT_EQ(c, (Vec3{0, 0, 1}));
  EXPECT_EQ(dot_fused({1, 2, 3}, {4, 5, 6}), 32.0);
}
