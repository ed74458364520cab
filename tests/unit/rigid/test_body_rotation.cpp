// Parmec's rotation kernel (spec parmec-springs §1.2) against closed forms: Rodrigues' formula, the
// Q3 typo's footprint, torque-free rigid-body invariants (second-order convergence), Gram-Schmidt.
#include <gtest/gtest.h>

#include <cmath>

#include "body_rotation.h"
#include "math/inertia.h"

using namespace dembridge::rigid;

namespace {
Mat3 inertia_from_list(const double *six) { return to_mat3(dembridge::math::inertia_from_list(six)); }
Mat3 rodrigues(const Vec3 &t) { return Eigen::AngleAxisd(t.norm(), t.normalized()).toRotationMatrix(); }
}  // namespace

TEST(BodyRotation, ExpmapIsRodriguesBothBranches)
{
  for (const Vec3 &t : {Vec3(0.3, -0.5, 0.8), Vec3(0.01, 0.02, -0.03), Vec3(0.1, 0.1, 0.05), Vec3(2.0, 1.0, -1.5)}) {
    const Mat3 E = expmap(t, false);
    EXPECT_LT((E - rodrigues(t)).norm(), 2e-15) << t.transpose();
    EXPECT_LT((E * E.transpose() - Mat3::Identity()).norm(), 2e-15);
  }
}

TEST(BodyRotation, Q3TypoOnlyWhereOmega1DiffersFromOmega2)
{
  const Vec3 same(0.2, 0.2, 0.3), diff(0.1, 0.2, 0.3);
  EXPECT_EQ((expmap(same, true) - expmap(same, false)).norm(), 0.0);
  const Mat3 d = expmap(diff, true) - expmap(diff, false);
  // only the (3,1) and (1,3) entries change, by cx·(Ω2Ω3 − Ω1Ω3)
  const double cx = (1.0 - std::cos(diff.norm())) / diff.squaredNorm();
  EXPECT_NEAR(d(0, 2), cx * (0.2 * 0.3 - 0.1 * 0.3), 1e-15);
  EXPECT_NEAR(d(2, 0), cx * (0.2 * 0.3 - 0.1 * 0.3), 1e-15);
  EXPECT_NEAR(d.norm(), std::sqrt(2.0) * std::abs(d(0, 2)), 1e-16);
}

TEST(BodyRotation, InertiaList)
{
  const double s[6] = {1, 2, 3, 0.1, 0.2, 0.3};
  const Mat3 J = inertia_from_list(s);
  EXPECT_EQ(J(0, 1), 0.1);
  EXPECT_EQ(J(1, 0), 0.1);
  EXPECT_EQ(J(0, 2), 0.2);
  EXPECT_EQ(J(2, 1), 0.3);
  EXPECT_EQ(J(2, 2), 3.0);
}

TEST(BodyRotation, IsotropicSpinIsExactRotationAboutOmega)
{
  const Mat3 J = 2.0 * Mat3::Identity();
  Mat3 L = Mat3::Identity();
  Vec3 W(0.0, 0.0, 1.0);
  const double h = 0.01;
  for (int n = 0; n < 100; n++) {
    const RotationStep s = rotation_step(J, J.inverse(), L, W, Vec3::Zero(), h, false);
    L = s.L;
    W = s.W;
  }
  EXPECT_EQ(W, Vec3(0, 0, 1));
  EXPECT_LT((L - rodrigues(Vec3(0, 0, 1.0))).norm(), 1e-13);
}

// Torque-free anisotropic body: spatial angular momentum Λ J Ω is an invariant of the continuous motion.
// Λ lives at half steps and Ω at whole steps, so Λ_{n+1/2} J Ω_n carries an O(h) offset: the difference
// after a fixed time halves with h (first-order convergence to the invariant).
TEST(BodyRotation, TorqueFreeInvariantsConvergeSecondOrder)
{
  const double s[6] = {1.0, 2.0, 3.5, 0.1, -0.2, 0.05};
  const Mat3 J = inertia_from_list(s);
  auto drift = [&](double h) {
    Mat3 L = Mat3::Identity();
    Vec3 W(0.4, 1.1, -0.7);
    const Vec3 M0 = J * W;
    const double E0 = 0.5 * W.dot(J * W);
    const int n = static_cast<int>(std::lround(2.0 / h));
    for (int k = 0; k < n; k++) {
      const RotationStep st = rotation_step(J, J.inverse(), L, W, Vec3::Zero(), h, false);
      L = st.L;
      W = st.W;
    }
    return std::make_pair((L * J * W - M0).norm() / M0.norm(), std::abs(0.5 * W.dot(J * W) - E0) / E0);
  };
  const auto a = drift(0.01), b = drift(0.005);
  EXPECT_LT(a.first, 1e-2);
  EXPECT_GT(a.first / b.first, 1.8);  // O(h)
  EXPECT_LT(a.first / b.first, 2.2);
  EXPECT_LT(a.second, 1e-2);
  EXPECT_LT(b.second, a.second);
}

TEST(BodyRotation, GramSchmidtAndProjection)
{
  const double d[9] = {2, 0, 0, 1, 1, 0, 3, 0, 0};  // third is dependent: dropped
  Vec3 b[3];
  EXPECT_EQ(orthonormalise(d, 3, b), 2);
  EXPECT_LT((b[0] - Vec3(1, 0, 0)).norm(), 1e-16);
  EXPECT_LT((b[1] - Vec3(0, 1, 0)).norm(), 1e-16);
  EXPECT_LT((remove_components(Vec3(1, 2, 3), b, 2) - Vec3(0, 0, 3)).norm(), 1e-16);
  EXPECT_EQ(remove_components(Vec3(1, 2, 3), b, 0), Vec3(1, 2, 3));
}

TEST(BodyRotation, SinglePrecisionSeriesQ26)
{
  // Parmec's ISPC kernels use float-rounded Taylor coefficients: about z, sin(θ)/θ is off by
  // (float(1/6) − 1/6)·θ² to leading order, so L(1,0) = sin θ − (float(1/6) − 1/6) θ³ + O(θ⁵·1e-9)
  const double th = 0.01, d6 = double(float(1.666666666666667E-1)) - 1.666666666666667E-1;
  const Mat3 E = expmap(Vec3(0, 0, th), false, true), X = expmap(Vec3(0, 0, th), false, false);
  EXPECT_NEAR(X(1, 0), std::sin(th), 1e-18);
  EXPECT_NEAR((E(1, 0) - X(1, 0)) / (-d6 * th * th * th), 1.0, 1e-3);
  // large angles use sin/cos in both (the series' threshold is |θ|² < 0.0305)
  EXPECT_EQ((expmap(Vec3(0.3, 0.1, 0), false, true) - expmap(Vec3(0.3, 0.1, 0), false, false)).norm(), 0.0);
}

TEST(BodyRotation, ParmecInverseIsTheInverse)
{
  const double s[6] = {3.0, 2.5, 4.0, 0.3, -0.2, 0.1};
  const Mat3 J = inertia_from_list(s), I = parmec_inverse(J);
  EXPECT_LT((J * I - Mat3::Identity()).norm(), 4e-16);
  // diagonal: (J11 J22) / (J00 J11 J22) as Parmec forms it, not 1/J00
  const double d[6] = {3.0, 7.0, 11.0, 0, 0, 0};
  const Mat3 D = parmec_inverse(inertia_from_list(d));
  EXPECT_EQ(D(0, 0), (7.0 * 11.0 - 0.0 * 0.0) * (1.0 / (3.0 * (7.0 * 11.0 - 0.0) + 0.0 * (0.0 - 0.0) + (0.0 - 0.0) * 0.0)));
  EXPECT_EQ(D(0, 1), 0.0);
}

TEST(BodyRotation, RestraintProjectionsAreSequential)
{
  // each component removed from the already reduced vector (Parmec's restrain kernels): with a non-
  // orthogonal pair the result differs from removing both components of the original vector
  const Vec3 b[3] = {Vec3(1, 0, 0), Vec3(std::sqrt(0.5), std::sqrt(0.5), 0), Vec3::Zero()};
  const Vec3 v(1, 2, 3), r = remove_components(v, b, 2);
  const Vec3 step1 = v - v.dot(b[0]) * b[0];
  EXPECT_EQ(r, step1 - step1.dot(b[1]) * b[1]);
}
