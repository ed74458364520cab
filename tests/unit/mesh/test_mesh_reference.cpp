// Topology, per-triangle geometry, placement and sphere-triangle contact against the independent
// Python model of LIGGGHTS 3.8 (spec_check_walls.py), bit for bit (EXPECT_EQ on doubles).
#include "reference_file.h"

#include "mesh_placement.h"
#include "stl_reader.h"
#include "triangle_contact.h"

#include <gtest/gtest.h>

#include <set>

namespace dembridge::mesh::test {
namespace {

Vec3 vec(const std::vector<std::string> &t, std::size_t at) { return {num(t[at]), num(t[at + 1]), num(t[at + 2])}; }

void expect_vec(const Vec3 &got, const Vec3 &want, const std::string &what)
{
  for (int k = 0; k < 3; ++k) EXPECT_EQ(got[k], want[k]) << what << " component " << k;
}

struct Counts {
  int probes = 0, hits = 0, faces = 0, edges = 0, corners = 0;
};

Counts check_against_reference(const TriangleMesh &m, const std::string &ref)
{
  const auto lines = read_ref(ref);
  std::set<std::pair<int, int>> coplanar_ref;
  Counts c;
  for (const auto &t : lines) {
    if (t[0] == "ntri") {
      EXPECT_EQ(m.size(), std::stoi(t[1]));
    } else if (t[0] == "tri") {
      const int tri = std::stoi(t[1]);
      const std::string tag = ref + " triangle " + t[1];
      if (t[2] == "nodes") {
        for (int k = 0; k < 3; ++k) expect_vec(m.node(tri, k), vec(t, 3 + 3 * k), tag + " node");
      } else if (t[2] == "geom") {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.edge_len(tri, k), num(t[3 + k])) << tag << " edge length " << k;
        expect_vec(m.normal(tri), vec(t, 6), tag + " normal");
        for (int k = 0; k < 3; ++k) expect_vec(m.edge_vec(tri, k), vec(t, 9 + 3 * k), tag + " edge vector");
        EXPECT_EQ(m.obtuse(tri), std::stoi(t[18])) << tag;
        EXPECT_EQ(m.rbound(tri), num(t[19])) << tag;
      } else if (t[2] == "active") {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.edge_active(tri, k), t[3 + k] == "1") << tag << " edge " << k;
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.corner_active(tri, k), t[6 + k] == "1") << tag << " corner " << k;
      }
    } else if (t[0] == "coplanar") {
      coplanar_ref.insert({std::stoi(t[1]), std::stoi(t[2])});
    } else if (t[0] == "probe") {
      const int tri = std::stoi(t[1]);
      const Vec3 p = vec(t, 2);
      const double r = num(t[5]);
      const TriangleContact got = resolve_contact(m, tri, p, r);
      const std::string tag = ref + " probe on triangle " + t[1] + " at " + t[2] + " " + t[3] + " " + t[4];
      ++c.probes;
      EXPECT_EQ(got.dist_minus_r, num(t[7])) << tag;
      if (t[6] == "none") {
        EXPECT_EQ(got.kind, ContactKind::None) << tag;
        EXPECT_EQ(got.sign, std::stoi(t[8])) << tag;
      } else {
        ++c.hits;
        EXPECT_NE(got.kind, ContactKind::None) << tag;
        expect_vec(got.delta, vec(t, 8), tag + " delta");
        expect_vec(got.bary, vec(t, 11), tag + " bary");
        EXPECT_EQ(got.sign, std::stoi(t[14])) << tag;
        c.faces += got.kind == ContactKind::Face;
        c.edges += got.kind == ContactKind::Edge;
        c.corners += got.kind == ContactKind::Corner;
      }
    }
  }
  for (int a = 0; a < m.size(); ++a)
    for (int b = 0; b < m.size(); ++b)
      if (a != b) {
        EXPECT_EQ(m.coplanar_node_neighbors(a, b), coplanar_ref.count({a, b}) == 1) << ref << " " << a << "," << b;
      }
  return c;
}

class MeshReference : public ::testing::TestWithParam<const char *> {};

TEST_P(MeshReference, TopologyGeometryAndContactsAreBitIdentical)
{
  const std::string stl = GetParam();
  const TriangleMesh m(read_stl(data_path(stl)));
  const Counts c = check_against_reference(m, stl.substr(0, stl.size() - 4) + ".ref");
  EXPECT_GT(c.probes, 100);
  EXPECT_GT(c.hits, 20);
  EXPECT_GT(c.faces, 0);
  EXPECT_GT(c.edges + c.corners, 0);  // the edge/corner rules are exercised, not only faces
}

// Beyond an obtuse corner (the node LIGGGHTS flags) the closest point may lie on either adjacent
// edge; its barycentric weights are the wall velocity's (spec §7.1). 73 probes in that corner's
// wedge, 36 on the edge before the corner and 37 on the edge after it.
TEST(MeshReferenceObtuseCorner, EdgeBranchesAreBitIdentical)
{
  const TriangleMesh m(read_stl(data_path("obtuse_corner.stl")));
  ASSERT_EQ(m.obtuse(0), 2);
  const Counts c = check_against_reference(m, "obtuse_corner.ref");
  EXPECT_EQ(c.probes, 73);
  EXPECT_EQ(c.edges, 73);
}

INSTANTIATE_TEST_SUITE_P(OracleMeshes, MeshReference,
                         ::testing::Values("plate.stl", "box.stl", "paddle.stl", "pusher.stl", "funnel_snapped.stl", "obtuse.stl"));

TEST(MeshTopology, NodesWithinPrecisionAreOneNode)
{
  // funnel.stl closes its cone with seam nodes 1.5e-18 apart; LIGGGHTS compares nodes with the
  // precision (1e-8), so the seam edges are shared exactly as in the snapped copy.
  const TriangleMesh raw(read_stl(data_path("funnel.stl")));
  const TriangleMesh snapped(read_stl(data_path("funnel_snapped.stl")));
  ASSERT_EQ(raw.size(), snapped.size());
  int differing_nodes = 0;
  for (int t = 0; t < raw.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(raw.edge_active(t, k), snapped.edge_active(t, k)) << t << " " << k;
      EXPECT_EQ(raw.corner_active(t, k), snapped.corner_active(t, k)) << t << " " << k;
      differing_nodes += raw.node(t, k) != snapped.node(t, k);
    }
    EXPECT_EQ(raw.node_neighbors(t), snapped.node_neighbors(t));
  }
  EXPECT_GT(differing_nodes, 0);
}

TEST(MeshPlacement, ScaleRotateMoveInCommandOrderMatchesReference)
{
  auto tris = read_stl(data_path("plate.stl"));
  apply_placement(tris, {{PlacementOp::Scale, {}, 0.8},
                         {PlacementOp::Rotate, {1.0, 0.0, 0.0}, 20.0},
                         {PlacementOp::Move, {0.0, 0.0, 0.003}, 0.0}});
  const TriangleMesh m(tris);
  check_against_reference(m, "plate_placed.ref");
}

TEST(MeshPlacement, RotateUsesLiggghtsTruncatedPi)
{
  // A unit x vector rotated about z by 90 degrees: with pi = 3.14159265 the result is off the
  // exact (0,1,0) by cos(pi_trunc/2) ~ 1.8e-9 in x (the quirk of spec §10.8).
  std::vector<TriangleNodes> tris{{Vec3{1.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 1.0}}};
  apply_placement(tris, {{PlacementOp::Rotate, {0.0, 0.0, 2.0}, 90.0}});
  const double phi = 90.0 * 3.14159265 / 180.0;
  EXPECT_NEAR(tris[0][0][0], std::cos(phi), 1e-16);
  EXPECT_NEAR(tris[0][0][0], 1.79489661e-9, 1e-15);
  EXPECT_NEAR(tris[0][0][1], 1.0, 1e-15);
}

TEST(MeshPlacement, OrderOfOperationsMatters)
{
  std::vector<TriangleNodes> a{{Vec3{1.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, Vec3{0.0, 1.0, 0.0}}}, b = a;
  apply_placement(a, {{PlacementOp::Move, {1.0, 0.0, 0.0}, 0.0}, {PlacementOp::Scale, {}, 2.0}});
  apply_placement(b, {{PlacementOp::Scale, {}, 2.0}, {PlacementOp::Move, {1.0, 0.0, 0.0}, 0.0}});
  EXPECT_EQ(a[0][1][0], 2.0);  // (0+1)*2
  EXPECT_EQ(b[0][1][0], 1.0);  // 0*2+1
}

TEST(MeshTopology, PlateMatchesTheSpecExample)
{
  // spec §4.3: diagonal inactive on both; corner C and A only on triangle 1, B on 0, D on 1
  const TriangleMesh m(read_stl(data_path("plate.stl")));
  EXPECT_FALSE(m.edge_active(0, 2));  // 0 = (A,B,C): edge 2 = C->A
  EXPECT_FALSE(m.edge_active(1, 0));  // 1 = (A,C,D): edge 0 = A->C
  EXPECT_TRUE(m.edge_active(0, 0) && m.edge_active(0, 1) && m.edge_active(1, 1) && m.edge_active(1, 2));
  EXPECT_FALSE(m.corner_active(0, 0));
  EXPECT_TRUE(m.corner_active(0, 1));
  EXPECT_FALSE(m.corner_active(0, 2));
  EXPECT_TRUE(m.corner_active(1, 0) && m.corner_active(1, 1) && m.corner_active(1, 2));
  EXPECT_TRUE(m.coplanar_node_neighbors(0, 1));
}

TEST(MeshTopology, CurvatureOptionDecidesCoplanarity)
{
  // two triangles folded by 10 degrees along a shared edge: coplanar only for curvature > 10 deg
  const double a = 10.0 * 3.14159265358979323846 / 180.0;
  std::vector<TriangleNodes> tris{{Vec3{0.0, 0.0, 0.0}, Vec3{1.0, 0.0, 0.0}, Vec3{0.0, 1.0, 0.0}},
                                  {Vec3{1.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, Vec3{0.0, -std::cos(a), std::sin(a)}}};
  MeshOptions opt;
  const TriangleMesh sharp(tris, opt);
  EXPECT_FALSE(sharp.coplanar_node_neighbors(0, 1));
  EXPECT_FALSE(sharp.edge_active(0, 0));  // shared edge active only on the later triangle
  EXPECT_TRUE(sharp.edge_active(1, 0));
  opt.curvature = std::cos(15.0 * 3.14159265358979323846 / 180.0);
  const TriangleMesh smooth(tris, opt);
  EXPECT_TRUE(smooth.coplanar_node_neighbors(0, 1));
  EXPECT_FALSE(smooth.edge_active(0, 0));
  EXPECT_FALSE(smooth.edge_active(1, 0));
}

TEST(MeshTopology, HealRemovesDuplicateTriangles)
{
  std::vector<TriangleNodes> tris{{Vec3{0.0, 0.0, 0.0}, Vec3{1.0, 0.0, 0.0}, Vec3{0.0, 1.0, 0.0}},
                                  {Vec3{1.0, 0.0, 0.0}, Vec3{0.0, 1.0, 0.0}, Vec3{0.0, 0.0, 1e-10}},
                                  {Vec3{1.0, 1.0, 0.0}, Vec3{0.0, 1.0, 0.0}, Vec3{1.0, 0.0, 0.0}}};
  const TriangleMesh kept(tris);
  EXPECT_EQ(kept.size(), 3);
  MeshOptions opt;
  opt.heal_remove_duplicates = true;
  const TriangleMesh healed(tris, opt);
  EXPECT_EQ(healed.size(), 2);
  EXPECT_EQ(healed.removed_duplicates(), 1);
  EXPECT_EQ(healed.node(1, 0)[0], 1.0);  // the third triangle moved up, order otherwise kept
  EXPECT_EQ(healed.node(1, 0)[1], 1.0);
}

TEST(MeshContact, FaceContactOfAxisAlignedPlateEqualsThePlaneLaw)
{
  // spec §4.4: for an exactly axis-aligned normal the face branch gives the primitive plane's bits
  const TriangleMesh m(read_stl(data_path("plate.stl")));
  const Vec3 p{0.003, -0.001, 0.0027};
  const TriangleContact c = resolve_contact(m, 0, p, 0.003);
  EXPECT_EQ(c.kind, ContactKind::Face);
  EXPECT_EQ(c.dist_minus_r, p[2] - 0.0 - 0.003);
  EXPECT_EQ(c.delta[0], 0.0);
  EXPECT_EQ(c.delta[1], 0.0);
  EXPECT_EQ(c.delta[2], 0.0 - p[2]);
}

}  // namespace
}  // namespace dembridge::mesh::test
