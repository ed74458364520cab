// The math layer's inertia tensors against closed forms: the solid sphere and box, a box of point masses,
// the parallel-axis shift of a cube to its edge, a non-diagonal tensor's inverse and principal moments, a
// rotated box's principal moments, and Sylvester's test.
#include "math/inertia.h"

#include <gtest/gtest.h>

using namespace dembridge::math;

namespace {

constexpr double kTol = 1e-14;

void expect_diagonal(const Mat9 &J, double xx, double yy, double zz, double tol)
{
  const double want[9] = {xx, 0, 0, 0, yy, 0, 0, 0, zz};
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(J[k], want[k], tol * std::fabs(xx)) << "entry " << k;
}

TEST(Inertia, SolidSphereIsTwoFifthsMR2)
{
  const Mat9 J = sphere_inertia(3.0, 0.5);  // 2/5 3 0.25 = 0.3
  expect_diagonal(J, 0.3, 0.3, 0.3, kTol);
}

TEST(Inertia, SolidBoxAndBoxOfPointMasses)
{
  const double m = 6.0, a = 1.0, b = 2.0, c = 3.0;
  expect_diagonal(box_inertia(m, {a, b, c}), m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12,
                  kTol);
  // m/8 at each corner (±a/2, ±b/2, ±c/2): Ixx = m (b² + c²) / 4, products of inertia cancel
  Mat9 J{};
  for (int k = 0; k < 8; ++k) {
    const Vec3 r = {(k & 1 ? 0.5 : -0.5) * a, (k & 2 ? 0.5 : -0.5) * b, (k & 4 ? 0.5 : -0.5) * c};
    const Mat9 P = point_inertia(m / 8, r);
    for (int e = 0; e < 9; ++e) J[e] += P[e];
  }
  expect_diagonal(J, m * (b * b + c * c) / 4, m * (a * a + c * c) / 4, m * (a * a + b * b) / 4, kTol);
}

TEST(Inertia, ParallelAxisCubeAboutItsEdge)
{
  // a cube of side s about an edge along z through (s/2, s/2) from the centre: Izz = 2/3 m s², and the
  // product Ixy = -m d_x d_y = -m s²/4
  const double m = 2.0, s = 0.4;
  const Mat9 J = parallel_axis(box_inertia(m, {s, s, s}), m, {s / 2, s / 2, 0.0});
  EXPECT_NEAR(J[8], 2.0 / 3.0 * m * s * s, kTol);
  EXPECT_NEAR(J[0], m * s * s / 6 + m * s * s / 4, kTol);
  EXPECT_NEAR(J[1], -m * s * s / 4, kTol);
  EXPECT_EQ(J[1], J[3]);
  EXPECT_EQ(J[2], 0.0);
  EXPECT_EQ(J[5], 0.0);
}

TEST(Inertia, NonDiagonalInverseAndPrincipalMoments)
{
  // [[2,1,1],[1,2,1],[1,1,2]]: det 4, inverse (1/4)[[3,-1,-1],[-1,3,-1],[-1,-1,3]] (exact in binary),
  // principal moments 1, 1, 4
  const double six[6] = {2, 2, 2, 1, 1, 1};
  const Mat9 J = inertia_from_list(six);
  const Mat9 want = {0.75, -0.25, -0.25, -0.25, 0.75, -0.25, -0.25, -0.25, 0.75};
  EXPECT_EQ(inverse_parmec(J), want);
  EXPECT_EQ(inverse_inertia(J), want);
  const Vec3 p = principal_moments(J);
  EXPECT_NEAR(p[0], 1.0, kTol);
  EXPECT_NEAR(p[1], 1.0, kTol);
  EXPECT_NEAR(p[2], 4.0, kTol);
  EXPECT_TRUE(positive_definite(J));
}

TEST(Inertia, RotatedBoxKeepsItsPrincipalMoments)
{
  // R diag(1, 2, 5) Rᵀ, R a rotation by 0.7 about (1, 2, 2)/3
  const Mat9 R = rotation_of_vector({0.7 / 3, 1.4 / 3, 1.4 / 3});
  const Mat9 D = {1, 0, 0, 0, 2, 0, 0, 0, 5};
  Mat9 Rt;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Rt[3 * i + j] = R[3 * j + i];
  const Mat9 J = mat_mul(mat_mul(R, D), Rt);
  const Vec3 p = principal_moments(J);
  EXPECT_NEAR(p[0], 1.0, 1e-13);
  EXPECT_NEAR(p[1], 2.0, 1e-13);
  EXPECT_NEAR(p[2], 5.0, 1e-13);
  const Mat9 I = mat_mul(J, inverse_inertia(J));
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(I[k], k % 4 == 0 ? 1.0 : 0.0, 1e-14) << "entry " << k;
}

TEST(Inertia, DiagonalInverseAndBodiesWithoutInertia)
{
  const Mat9 J = {4, 0, 0, 0, 0.5, 0, 0, 0, 0};  // a zero moment: no rotation about z
  const Mat9 want = {0.25, 0, 0, 0, 2, 0, 0, 0, 0};
  EXPECT_EQ(inverse_inertia(J), want);
  EXPECT_FALSE(positive_definite(J));
  const Mat9 singular = {1, 1, 0, 1, 1, 0, 0, 0, 1};  // Ixy = Ixx: one principal moment zero
  EXPECT_EQ(inverse_inertia(singular), Mat9{});
  EXPECT_FALSE(positive_definite(singular));
  EXPECT_FALSE(positive_definite(Mat9{}));
}

}  // namespace
