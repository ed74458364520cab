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
  distribute_contacts(m, map, c, p.data());
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
  distribute_contacts(m, map, r, q.data());
  EXPECT_EQ(p, q);
}

}  // namespace
}  // namespace dembridge::mesh::test
