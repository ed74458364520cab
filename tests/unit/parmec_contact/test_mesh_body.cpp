// MESH body surfaces: triangles placed at x + Λ(P − X) from the body's pose, material velocity v + ω × (p − x).
#include "mesh_body.h"
#include "unit_square.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

using namespace dembridge::parmec_contact;
using dembridge::mesh::TriangleNodes;

namespace {

// the unit square z = 1 in the reference configuration, body centre X = (0.5, 0.5, 0.5)
std::vector<TriangleNodes> top() { return unit_square(1.0); }

}  // namespace

TEST(MeshBody, PlacesTheTrianglesAtTheBodyPose)
{
  MeshBody b(7, top(), {3, 4}, Vec3{0.5, 0.5, 0.5});
  EXPECT_EQ(b.tag(), 7);
  EXPECT_EQ(b.surface().color(1), 4);
  BodyPose pose;
  pose.x = {10.0, 20.0, 30.0};
  // a quarter turn about z: (x, y, z) -> (-y, x, z)
  const double L[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  std::copy(L, L + 9, pose.lambda);
  pose.w = {0.0, 0.0, 2.0};
  pose.v = {1.0, 0.0, 0.0};
  b.place(pose);
  // node (1, 0, 1): arm (0.5, -0.5, 0.5) -> (0.5, 0.5, 0.5) -> (10.5, 20.5, 30.5)
  const Vec3 &p = b.surface().mesh().node(0, 1);
  EXPECT_DOUBLE_EQ(p[0], 10.5);
  EXPECT_DOUBLE_EQ(p[1], 20.5);
  EXPECT_DOUBLE_EQ(p[2], 30.5);
  EXPECT_DOUBLE_EQ(b.surface().mesh().normal(0)[2], 1.0);  // the top face still faces +z
  EXPECT_DOUBLE_EQ(b.surface().mesh().center(0)[2], 30.5);
  // v + w x (p - x) at p = x + (1, 0, 0): (1, 0, 0) + (0, 2, 0)
  const Vec3 u = b.velocity_at(Vec3{11.0, 20.0, 30.0});
  EXPECT_DOUBLE_EQ(u[0], 1.0);
  EXPECT_DOUBLE_EQ(u[1], 2.0);
  EXPECT_DOUBLE_EQ(u[2], 0.0);
  // back to the reference frame: the placed node (10.5, 20.5, 30.5) is the reference node (1, 0, 1)
  const Vec3 r = b.to_reference(p);
  EXPECT_DOUBLE_EQ(r[0], 1.0);
  EXPECT_DOUBLE_EQ(r[1], 0.0);
  EXPECT_DOUBLE_EQ(r[2], 1.0);
  EXPECT_DOUBLE_EQ(b.reference_mesh().node(0, 1)[0], 1.0);  // the reference triangles do not move
}

TEST(MeshBody, PoseRoundTripsThroughItsMessage)
{
  BodyPose p;
  p.x = {1, 2, 3};
  for (int k = 0; k < 9; k++) p.lambda[k] = 10 + k;
  p.v = {4, 5, 6};
  p.w = {7, 8, 9};
  p.mass = 42;
  double buf[BodyPose::kDoubles];
  p.pack(buf);
  const BodyPose q = BodyPose::unpack(buf);
  for (int k = 0; k < 3; k++) {
    EXPECT_EQ(q.x[k], p.x[k]);
    EXPECT_EQ(q.v[k], p.v[k]);
    EXPECT_EQ(q.w[k], p.w[k]);
  }
  for (int k = 0; k < 9; k++) EXPECT_EQ(q.lambda[k], p.lambda[k]);
  EXPECT_EQ(q.mass, 42);
}

TEST(MeshBody, BadColoursAreRefusedAsForAnObstacle)
{
  EXPECT_THROW(MeshBody(1, top(), {1}, Vec3{0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(MeshBody(1, top(), {1, 0}, Vec3{0, 0, 0}), std::invalid_argument);
}

TEST(MeshBody, ABodyAtRestKeepsItsTriangles)
{
  MeshBody b(1, top(), {1, 1}, Vec3{0.5, 0.5, 0.5});
  BodyPose pose;
  pose.x = {0.5, 0.5, 0.5};
  b.place(pose);
  const auto v0 = b.surface().mesh().geometry_version();
  pose.v = {1.0, 0.0, 0.0};  // velocities change, the pose does not: same triangles, new material velocity
  b.place(pose);
  EXPECT_EQ(b.surface().mesh().geometry_version(), v0);
  EXPECT_DOUBLE_EQ(b.velocity_at(Vec3{0, 0, 0})[0], 1.0);
  pose.x[2] = 0.75;
  b.place(pose);
  EXPECT_NE(b.surface().mesh().geometry_version(), v0);
  EXPECT_DOUBLE_EQ(b.surface().mesh().node(0, 0)[2], 1.25);
}
