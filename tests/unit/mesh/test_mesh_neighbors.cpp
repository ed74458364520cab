// Binned candidate search: same candidates as testing every triangle (the LIGGGHTS criterion),
// ascending ids, and per-particle work independent of the triangle count (10^5 triangles).
#include "reference_file.h"

#include "mesh_neighbors.h"
#include "stl_reader.h"
#include "triangle_contact.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

namespace dembridge::mesh::test {
namespace {

// a wavy sheet of 2*nx*ny triangles over [0,1]^2
TriangleMesh wavy_sheet(int nx, int ny)
{
  std::vector<TriangleNodes> tris;
  auto z = [](double x, double y) { return 0.05 * std::sin(6.0 * x) * std::cos(5.0 * y); };
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double x0 = double(i) / nx, x1 = double(i + 1) / nx, y0 = double(j) / ny, y1 = double(j + 1) / ny;
      const Vec3 a{x0, y0, z(x0, y0)}, b{x1, y0, z(x1, y0)}, c{x1, y1, z(x1, y1)}, d{x0, y1, z(x0, y1)};
      tris.push_back({a, b, c});
      tris.push_back({a, c, d});
    }
  return TriangleMesh(tris);
}

struct Particles {
  std::vector<std::array<double, 3>> pos;
  std::vector<const double *> x;
  std::vector<double> r;
};

Particles random_particles(int n, unsigned seed, double rmin, double rmax)
{
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-0.1, 1.1), uz(-0.15, 0.15), ur(rmin, rmax);
  Particles p;
  p.pos.resize(n);
  for (auto &q : p.pos) q = {u(gen), u(gen), uz(gen)};
  for (auto &q : p.pos) p.x.push_back(q.data());
  for (int i = 0; i < n; ++i) p.r.push_back(ur(gen));
  return p;
}

TEST(MeshNeighbors, SameCandidatesAsBruteForce)
{
  const TriangleMesh m = wavy_sheet(20, 15);
  Particles p = random_particles(3000, 7, 0.005, 0.02);
  std::vector<int> skip(p.r.size(), 0);
  skip[5] = 1;
  MeshNeighbors nb;
  const double s = 0.004;
  nb.build(m, int(p.r.size()), p.x.data(), p.r.data(), skip.data(), s);
  std::size_t total = 0;
  for (int i = 0; i < int(p.r.size()); ++i) {
    std::vector<int> brute;
    if (!skip[i])
      for (int t = 0; t < m.size(); ++t)
        if (MeshNeighbors::in_reach(m, t, {p.x[i][0], p.x[i][1], p.x[i][2]}, p.r[i] + s)) brute.push_back(t);
    std::vector<int> got(nb.begin(i), nb.begin(i) + nb.count(i));
    EXPECT_EQ(got, brute) << "particle " << i;
    total += brute.size();
  }
  EXPECT_GT(total, 500u);
  EXPECT_EQ(nb.count(5), 0);
}

TEST(MeshNeighbors, EveryContactIsACandidate)
{
  // the list is a superset of the contacts: no touching triangle is ever missing
  const TriangleMesh m(read_stl(data_path("box.stl")));
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-0.03, 0.03);
  int contacts = 0;
  for (int n = 0; n < 4000; ++n) {
    std::array<double, 3> q{u(gen), u(gen), u(gen)};
    const double *x = q.data();
    const double r = 0.004;
    MeshNeighbors nb;
    nb.build(m, 1, &x, &r, nullptr, 0.0005);
    for (int t = 0; t < m.size(); ++t) {
      const TriangleContact c = resolve_contact(m, t, {q[0], q[1], q[2]}, r);
      if (c.dist_minus_r <= 0.0) {
        ++contacts;
        EXPECT_NE(std::find(nb.begin(0), nb.begin(0) + nb.count(0), t), nb.begin(0) + nb.count(0));
      }
    }
  }
  EXPECT_GT(contacts, 100);
}

TEST(MeshNeighbors, HundredThousandTrianglesWorkAndCostDoesNotScaleWithTriangles)
{
  const TriangleMesh small = wavy_sheet(20, 25);    // 1000 triangles
  const TriangleMesh big = wavy_sheet(250, 200);    // 100000 triangles
  ASSERT_EQ(big.size(), 100000);
  // particles of the same size relative to the triangles in both cases
  Particles ps = random_particles(20000, 11, 0.01, 0.02);
  Particles pb = random_particles(20000, 11, 0.001, 0.002);
  MeshNeighbors a, b;
  a.build(small, 20000, ps.x.data(), ps.r.data(), nullptr, 0.002);
  b.build(big, 20000, pb.x.data(), pb.r.data(), nullptr, 0.0002);
  // work per particle = triangles tested = triangles in its bin
  const double per_particle_small = double(a.tests_performed()) / 20000.0;
  const double per_particle_big = double(b.tests_performed()) / 20000.0;
  std::printf("triangles tested per particle: %.2f (10^3 triangles), %.2f (10^5 triangles)\n", per_particle_small, per_particle_big);
  EXPECT_LT(per_particle_big, 3.0 * per_particle_small + 10.0);
  EXPECT_LT(per_particle_big, 100.0);  // vs 10^5 for testing every triangle
  EXPECT_GT(b.total(), 0u);
}


}  // namespace
}  // namespace dembridge::mesh::test

namespace dembridge::mesh::test {
namespace {

TEST(MeshNeighbors, BinsFollowTheMeshWhenItMoves)
{
  // the bins are cached for a static mesh; after a move the candidates must follow the mesh
  TriangleMesh m(read_stl(data_path("plate.stl")));
  std::array<double, 3> q{0.0, 0.001, 0.0031};
  const double *x = q.data();
  const double r = 0.003;
  MeshNeighbors nb;
  nb.build(m, 1, &x, &r, nullptr, 0.0005);
  EXPECT_EQ(nb.count(0), 2);
  nb.build(m, 1, &x, &r, nullptr, 0.0005);  // cached bins, same answer
  EXPECT_EQ(nb.count(0), 2);
  m.translate({0.0, 0.0, 0.01});            // the plate moves away
  nb.build(m, 1, &x, &r, nullptr, 0.0005);
  EXPECT_EQ(nb.count(0), 0);
  q[2] = 0.0131;
  nb.build(m, 1, &x, &r, nullptr, 0.0005);
  EXPECT_EQ(nb.count(0), 2);
}

// A rank's part of the mesh (keep_only): the candidates of a particle in the kept region are those of
// the whole mesh (file-order ids, same order); node-neighbour and coplanarity answers are the whole
// mesh's; an empty part builds and finds nothing.
TEST(MeshNeighbors, KeptPartFindsTheWholeMeshCandidates)
{
  const TriangleMesh whole = wavy_sheet(20, 15);
  TriangleMesh part = wavy_sheet(20, 15);
  std::vector<int> ids;
  for (int t = 0; t < whole.size(); ++t)
    if (whole.center(t)[0] < 0.5) ids.push_back(t);
  part.keep_only(ids);
  ASSERT_EQ(part.size(), int(ids.size()));
  EXPECT_EQ(part.global_size(), whole.size());
  EXPECT_FALSE(part.whole());
  Vec3 lo, hi, wlo, whi;
  part.bounding_box(lo, hi);
  whole.bounding_box(wlo, whi);
  EXPECT_EQ(lo, wlo);
  EXPECT_EQ(hi, whi);
  Particles p = random_particles(2000, 11, 0.005, 0.02);
  std::vector<int> skip(p.r.size(), 0);
  for (std::size_t i = 0; i < p.r.size(); ++i) skip[i] = p.pos[i][0] > 0.5 - 0.02 - 0.004 - 1.0 / 20;  // beyond the part's reach
  MeshNeighbors nw, np;
  nw.build(whole, int(p.r.size()), p.x.data(), p.r.data(), skip.data(), 0.004);
  np.build(part, int(p.r.size()), p.x.data(), p.r.data(), skip.data(), 0.004);
  std::size_t found = 0;
  for (int i = 0; i < int(p.r.size()); ++i) {
    ASSERT_EQ(np.count(i), nw.count(i)) << "particle " << i;
    for (int c = 0; c < nw.count(i); ++c) {
      const int t = np.begin(i)[c];
      ASSERT_EQ(part.global_id(t), nw.begin(i)[c]);
      ASSERT_EQ(part.local_id(part.global_id(t)), t);
      ASSERT_EQ(part.nodes(t), whole.nodes(nw.begin(i)[c]));
      for (int c2 = 0; c2 < nw.count(i); ++c2)
        ASSERT_EQ(part.coplanar_node_neighbors(t, np.begin(i)[c2]),
                  whole.coplanar_node_neighbors(nw.begin(i)[c], nw.begin(i)[c2]));
    }
    found += std::size_t(nw.count(i));
  }
  EXPECT_GT(found, 100u);
  EXPECT_EQ(part.local_id(whole.size() - 1), -1);  // a triangle at x near 1 is not kept
  TriangleMesh none = wavy_sheet(2, 2);
  none.keep_only({});
  MeshNeighbors ne;
  ne.build(none, int(p.r.size()), p.x.data(), p.r.data(), nullptr, 0.004);
  EXPECT_EQ(ne.total(), 0u);
  EXPECT_EQ(ne.count(0), 0);
}

}  // namespace
}  // namespace dembridge::mesh::test
