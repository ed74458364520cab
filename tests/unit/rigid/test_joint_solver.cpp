// Parmec's BALL_JOINT solve (spec parmec-springs §9) on closed forms: a body pinned at its centre holds
// gravity exactly, a point pinned off-centre keeps zero velocity to first order, a kinematic driver drags
// a body, clusters are the connected components, redundant constraints are reported as singular.
#include <gtest/gtest.h>

#include "joint_solver.h"

using namespace dembridge::rigid;

namespace {
BodyKinematics body(double m, double J, const Vec3 &force, double h)
{
  BodyKinematics b;
  b.inv_mass = 1.0 / m;
  b.inv_inertia = Mat3::Identity() / J;
  b.v_free = b.v + h / m * force;
  b.W_free = b.W;
  return b;
}
}  // namespace

TEST(JointSolver, PinnedAtCentreHoldsGravityExactly)
{
  JointDef d;
  d.body1 = 0;
  JointClusters c(1, {d});
  const double m = 3.0, h = 1e-3;
  const auto R = c.solve({body(m, 2.0, Vec3(0, 0, -10.0 * m), h)}, h, false);
  EXPECT_NEAR(R[0][2], 30.0, 1e-12);
  EXPECT_EQ(R[0][0], 0.0);
}

TEST(JointSolver, OffCentrePinKeepsThePointAtRest)
{
  // body at rest pinned at arm b; after the reaction the point's linear-response velocity is zero
  JointDef d;
  d.body1 = 0;
  d.arm1 = Vec3(0.5, 0.2, -0.1);
  JointClusters c(1, {d});
  const double h = 1e-3, m = 2.0, J = 0.7;
  BodyKinematics b = body(m, J, Vec3(1.0, -2.0, -19.6), h);
  const Vec3 R = c.solve({b}, h, false)[0];
  const Mat3 H = JointClusters::point_operator(b.L, d.arm1);
  const Vec3 v1 = b.v_free + h / m * R;
  const Vec3 W1 = b.W_free + b.inv_inertia * (H.transpose() * R) * h;
  EXPECT_LT((v1 + H * W1).norm(), 1e-15);
}

TEST(JointSolver, KinematicDriverDragsTheBody)
{
  // body 1 (kinematic, moving at u) joined at the centre of body 0: body 0's centre ends the step at
  // u·(U_rel(t_n) + U_rel(t_n+1) = 0 with U_rel(t_n) = 0 -> U0(t_n+1) = U1(t_n+1))
  JointDef d;
  d.body1 = 0;
  d.body2 = 1;
  JointClusters c(2, {d});
  const double h = 1e-2;
  BodyKinematics free = body(5.0, 1.0, Vec3::Zero(), h), drv;
  drv.v_free = Vec3(0.3, 0, 0);
  const Vec3 R = c.solve({free, drv}, h, false)[0];
  EXPECT_NEAR((free.v_free + h / 5.0 * R)[0], 0.3, 1e-15);
}

TEST(JointSolver, ClustersAreConnectedComponents)
{
  std::vector<JointDef> j(4);
  j[0].body1 = 0;                 // pin body 0
  j[1].body1 = 1, j[1].body2 = 0;  // chain 0-1
  j[2].body1 = 3, j[2].body2 = 2;  // separate pair 2-3
  j[3].body1 = 2;                 // pin body 2
  JointClusters c(4, j);
  ASSERT_EQ(c.clusters().size(), 2u);
  EXPECT_EQ(c.clusters()[0], (std::vector<int>{0, 1}));
  EXPECT_EQ(c.clusters()[1], (std::vector<int>{2, 3}));
}

TEST(JointSolver, RedundantPinIsSingular)
{
  std::vector<JointDef> j(2);
  j[0].body1 = 0;
  j[1].body1 = 0;  // the same point pinned twice
  JointClusters c(1, j);
  const double h = 1e-3;
  try {
    c.solve({body(1.0, 1.0, Vec3(0, 0, -1), h)}, h, false);
    FAIL() << "expected SingularCluster";
  } catch (SingularCluster &e) {
    EXPECT_EQ(e.joints, (std::vector<int>{0, 1}));
  }
}

TEST(JointSolver, BadBodyIndexThrows)
{
  JointDef d;
  d.body1 = 3;
  EXPECT_THROW(JointClusters(2, {d}), std::invalid_argument);
  d.body1 = 1;
  d.body2 = 1;
  EXPECT_THROW(JointClusters(2, {d}), std::invalid_argument);
}
