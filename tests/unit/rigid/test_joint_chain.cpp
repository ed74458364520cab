// A two-joint chain (body 0 pinned in space, body 1 hung from body 0) through the BALL_JOINT solve, on
// closed forms: the static chain carries the weights below each joint, and a rotating, moving chain meets
// both velocity constraints U_rel(t_n) + U_rel(t_n+1) = 0 once the reactions are applied. The joint of two
// bodies couples their rows with the sign of the shared body's side (part 1 or part 2), which only a chain
// (more than one joint in a cluster) exercises.
#include <gtest/gtest.h>

#include "joint_solver.h"

using namespace dembridge::rigid;

namespace {

Mat3 rotation(double angle, Vec3 axis)
{
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

BodyKinematics body(double m, const Mat3 &J, const Mat3 &L, const Vec3 &v, const Vec3 &W, const Vec3 &force, double h)
{
  BodyKinematics b;
  b.inv_mass = 1.0 / m;
  b.inv_inertia = J.inverse();
  b.L = L;
  b.v = v;
  b.W = W;
  b.v_free = v + h / m * force;
  b.W_free = W;
  return b;
}

// joint 0 pins body 0 at arm a0; joint 1 joins body 1 (part 1, arm b1) to body 0 (part 2, arm c1)
JointClusters chain(const Vec3 &a0, const Vec3 &b1, const Vec3 &c1)
{
  std::vector<JointDef> j(2);
  j[0].body1 = 0;
  j[0].arm1 = a0;
  j[1].body1 = 1;
  j[1].body2 = 0;
  j[1].arm1 = b1;
  j[1].arm2 = c1;
  return JointClusters(2, j);
}

struct After {
  Vec3 v, W;  // velocities at t_n+1 with the reactions applied
};

After apply(const BodyKinematics &b, double h, const std::vector<std::pair<Vec3, Vec3>> &force_at_arm)
{
  After a{b.v_free + b.kick, b.W_free};
  for (const auto &[F, arm] : force_at_arm) {
    const Mat3 H = JointClusters::point_operator(b.L, arm);
    a.v += h * b.inv_mass * F;
    a.W += h * b.inv_inertia * (H.transpose() * F);
  }
  return a;
}

Vec3 point_velocity(const BodyKinematics &b, const Vec3 &v, const Vec3 &W, const Vec3 &arm)
{
  return v + JointClusters::point_operator(b.L, arm) * W;
}

}  // namespace

TEST(JointChain, StaticChainCarriesTheWeightBelowEachJoint)
{
  // joint points straight above each centre: gravity has no moment, the chain stays at rest, so
  // R0 = (m0 + m1) g up at the pin and R1 = m1 g up on body 1 (down on body 0)
  const double h = 1e-3, g = 9.81, m0 = 2.0, m1 = 3.5;
  const Mat3 J0 = Vec3(0.3, 0.5, 0.7).asDiagonal(), J1 = Vec3(0.9, 0.4, 0.6).asDiagonal();
  const JointClusters c = chain(Vec3(0, 0, 0.4), Vec3(0, 0, 0.25), Vec3(0, 0, -0.4));
  ASSERT_EQ(c.clusters().size(), 1u);
  const std::vector<BodyKinematics> B = {
      body(m0, J0, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, -m0 * g), h),
      body(m1, J1, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, -m1 * g), h)};
  const auto R = c.solve(B, h, false);
  EXPECT_NEAR(R[0][2], (m0 + m1) * g, 1e-12 * (m0 + m1) * g);
  EXPECT_NEAR(R[1][2], m1 * g, 1e-12 * m1 * g);
  for (int k = 0; k < 2; k++) EXPECT_NEAR(std::hypot(R[0][k], R[1][k]), 0.0, 1e-12);
}

TEST(JointChain, MovingChainMeetsBothVelocityConstraints)
{
  const double h = 2e-3;
  const Mat3 J0 = (Mat3() << 0.5, 0.05, -0.02, 0.05, 0.4, 0.03, -0.02, 0.03, 0.3).finished();
  const Mat3 J1 = Vec3(0.8, 0.35, 0.6).asDiagonal();
  const Vec3 a0(0.1, -0.2, 0.45), b1(-0.15, 0.05, 0.3), c1(0.2, 0.1, -0.35);
  const JointClusters c = chain(a0, b1, c1);
  std::vector<BodyKinematics> B = {
      body(2.0, J0, rotation(0.7, Vec3(1, 2, 3)), Vec3(0.1, -0.3, 0.2), Vec3(1.0, -0.5, 2.0), Vec3(0.5, 0.2, -19.6), h),
      body(3.5, J1, rotation(-1.1, Vec3(-2, 1, 0.5)), Vec3(-0.2, 0.4, 0.1), Vec3(-0.7, 1.5, 0.3), Vec3(0, 1.0, -34.3), h)};
  B[1].kick = Vec3(0.01, -0.02, 0.005);
  const auto R = c.solve(B, h, false);
  const After A0 = apply(B[0], h, {{R[0], a0}, {-R[1], c1}}), A1 = apply(B[1], h, {{R[1], b1}});
  // joint 0: the pinned point of body 0; joint 1: body 1's point minus body 0's point
  const Vec3 u0_n = point_velocity(B[0], B[0].v, B[0].W, a0), u0_1 = point_velocity(B[0], A0.v, A0.W, a0);
  const Vec3 u1_n = point_velocity(B[1], B[1].v, B[1].W, b1) - point_velocity(B[0], B[0].v, B[0].W, c1);
  const Vec3 u1_1 = point_velocity(B[1], A1.v, A1.W, b1) - point_velocity(B[0], A0.v, A0.W, c1);
  const double scale = u0_n.norm() + u1_n.norm();
  EXPECT_LT((u0_n + u0_1).norm(), 1e-13 * scale);
  EXPECT_LT((u1_n + u1_1).norm(), 1e-13 * scale);
  EXPECT_GT(R[1].norm(), 1.0);  // the second joint really carries load
}
