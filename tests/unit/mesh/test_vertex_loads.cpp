// Vertex-driven meshes (fix mbdyn ... mapping): corners matched to driving points, the mesh placed
// from the points (geometry recomputed), and contact forces split to the points with barycentric
// weights, against closed forms.
#include "vertex_loads.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace dembridge::mesh::test {
namespace {

// the unit square as two triangles; the points in another order than the corners
TriangleMesh square()
{
  return TriangleMesh({{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}}, {Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}});
}
const std::vector<Vec3> kPoints{{1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}};

TEST(VertexLoads, CornersMatchTheirPoints)
{
  const CornerPoints map = match_corners(square(), kPoints, 1e-9);
  ASSERT_EQ(map.size(), 2u);
  EXPECT_EQ(map[0], (std::array<int, 3>{2, 3, 1}));
  EXPECT_EQ(map[1], (std::array<int, 3>{3, 0, 1}));
}

TEST(VertexLoads, ACornerWithoutPointOrWithTwoIsNamed)
{
  std::vector<Vec3> off = kPoints;
  off[3] = {1, 0, 1e-6};  // corner 2 of triangle 1 and corner 1 of triangle 2 lose their point
  try {
    match_corners(square(), off, 1e-9);
    FAIL() << "no error";
  } catch (const MeshError &e) {
    EXPECT_NE(std::string(e.what()).find("vertex 2 of triangle 1 at (1, 0, 0) has no mapped point within the match "
                                         "tolerance (the nearest, point 4, is 1e-06 away)"),
              std::string::npos)
        << e.what();
  }
  std::vector<Vec3> twice = kPoints;
  twice.push_back({0, 0, 1e-10});
  try {
    match_corners(square(), twice, 1e-9);
    FAIL() << "no error";
  } catch (const MeshError &e) {
    EXPECT_NE(std::string(e.what()).find("vertex 1 of triangle 1 at (0, 0, 0) is within the match tolerance of two "
                                         "mapped points, 3 and 5"),
              std::string::npos)
        << e.what();
  }
}

TEST(VertexLoads, PlacedFromThePointsTheGeometryFollows)
{
  TriangleMesh m = square();
  const CornerPoints map = match_corners(m, kPoints, 1e-9);
  std::vector<Vec3> moved = kPoints;
  moved[0] = {1, 1, 0.5};  // lift one corner: triangle 2 tilts, triangle 1 stays
  m.place_nodes(nodes_from_points(map, moved));
  EXPECT_EQ(m.node(1, 1), moved[0]);
  const Vec3 n1 = m.normal(1), n0 = m.normal(0);
  // (1,1,0.5)-(1,0,0) = (0,1,0.5), (0,1,0)-(1,0,0) = (-1,1,0): normal (-0.5,-0.5,1)/sqrt(1.5)
  const double s = 1 / std::sqrt(1.5);
  EXPECT_NEAR(n1[0], -0.5 * s, 1e-15);
  EXPECT_NEAR(n1[1], -0.5 * s, 1e-15);
  EXPECT_NEAR(n1[2], s, 1e-15);
  EXPECT_EQ(n0, (Vec3{0, 0, 1}));
}

TEST(VertexLoads, BarycentricWeightsOfAPointOnTheTriangle)
{
  const Vec3 w = barycentric(square(), 0, {0.2, 0.3, 0});
  EXPECT_NEAR(w[0], 0.5, 1e-15);
  EXPECT_NEAR(w[1], 0.2, 1e-15);
  EXPECT_NEAR(w[2], 0.3, 1e-15);
}

TEST(VertexLoads, ForcesSplitToThePointsKeepTheForceAndMoment)
{
  const TriangleMesh m = square();
  const CornerPoints map = match_corners(m, kPoints, 1e-9);
  std::vector<MeshContact> c{{0, {1, 2, 3}, {0.2, 0.3, 0}}, {1, {-0.5, 0.25, 2}, {0.9, 0.6, 0}},
                             {1, {0.125, 0, -1}, {1, 0.5, 0}}};
  std::vector<double> p(12, 0.0);
  distribute_contacts(m, map, c.data(), c.size(), p.data());
  // triangle 1's contact at weights (0.5, 0.2, 0.3): point 3 (the origin) gets half of it
  EXPECT_NEAR(p[3 * 2 + 0], 0.5, 1e-15);
  EXPECT_NEAR(p[3 * 2 + 2], 1.5, 1e-15);
  Vec3 F{0, 0, 0}, M{0, 0, 0}, Fc{0, 0, 0}, Mc{0, 0, 0};
  for (int j = 0; j < 4; ++j) {
    const Vec3 pj{p[3 * j], p[3 * j + 1], p[3 * j + 2]};
    F = add(F, pj);
    M = add(M, cross(kPoints[j], pj));
  }
  for (const MeshContact &k : c) {
    const Vec3 f{k.f[0], k.f[1], k.f[2]};
    Fc = add(Fc, f);
    Mc = add(Mc, cross({k.cp[0], k.cp[1], k.cp[2]}, f));
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(F[a], Fc[a], 1e-15);
    EXPECT_NEAR(M[a], Mc[a], 1e-15);
  }
  // the contacts in another order (another rank split): the same sums, bit for bit
  std::vector<MeshContact> r{c[2], c[0], c[1]};
  std::vector<double> q(12, 0.0);
  distribute_contacts(m, map, r.data(), r.size(), q.data());
  EXPECT_EQ(p, q);
}

// Contacts on one triangle that differ only past their first word, with forces whose sum depends on
// the order (1e16 + 1 - 1e16): every arrival order gives the same loads, bit for bit.
TEST(VertexLoads, TheOrderIsCanonicalBeyondTheTriangle)
{
  const TriangleMesh m = square();
  const CornerPoints map = match_corners(m, kPoints, 1e-9);
  std::vector<MeshContact> c{{0, {1e16, 0, 0}, {0.2, 0.3, 0}}, {0, {1, 0, 0}, {0.2, 0.3, 0}},
                             {0, {-1e16, 0, 0}, {0.2, 0.3, 0}}, {0, {1, 0, 0}, {0.1, 0.3, 0}}};
  std::vector<int> perm{0, 1, 2, 3};
  std::vector<double> first;
  do {
    std::vector<MeshContact> r;
    for (int k : perm) r.push_back(c[k]);
    std::vector<double> q(12, 0.0);
    distribute_contacts(m, map, r.data(), r.size(), q.data());
    if (first.empty()) first = q;
    EXPECT_EQ(q, first);
  } while (std::next_permutation(perm.begin(), perm.end()));
}

// place_corners: the nodes and velocities of the corners' points, the geometry as place_nodes gives it.
TEST(VertexLoads, PlaceCornersEqualsPlaceNodesAndVelocities)
{
  TriangleMesh a = square(), b = square();
  const CornerPoints map = match_corners(a, kPoints, 1e-9);
  const std::vector<Vec3> x{{1.1, 0.9, 0.2}, {0.0, 1.2, -0.1}, {0.05, 0.0, 0.0}, {1.0, 0.1, 0.3}};
  const std::vector<Vec3> v{{-0.0, 1.0, 2.0}, {3.0, -0.0, 1e-300}, {0.5, 0.25, -1.0}, {7.0, 8.0, 9.0}};
  a.place_nodes(nodes_from_points(map, x));
  a.zero_velocity();
  for (int t = 0; t < a.size(); ++t)
    for (int k = 0; k < 3; ++k) a.add_node_velocity(t, k, v[map[t][k]]);
  b.place_corners(map, x, v);
  for (int t = 0; t < a.size(); ++t) {
    EXPECT_EQ(a.nodes(t), b.nodes(t));
    EXPECT_EQ(a.normal(t), b.normal(t));
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.node_velocity(t, k), b.node_velocity(t, k));
      EXPECT_FALSE(std::signbit(b.node_velocity(t, k)[0]));  // 0.0 + (-0.0)
      EXPECT_EQ(a.edge_norm(t, k), b.edge_norm(t, k));
    }
  }
  EXPECT_THROW(b.place_corners(CornerPoints(1), x, v), MeshError);
}

}  // namespace
}  // namespace dembridge::mesh::test
