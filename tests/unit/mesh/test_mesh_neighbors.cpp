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

namespace dembridge::mesh::test {
namespace {

// the benchmark's hopper: a cone (r 0.012 at z 0 to 0.06 at z 0.06) under a cylinder to z 0.1, 64 triangles
TriangleMesh hopper()
{
  std::vector<TriangleNodes> tris;
  const int nseg = 32;
  auto ring = [&](double r, double z, int k) {
    const double a = 2.0 * 3.14159265358979323846 * k / nseg;
    return Vec3{r * std::cos(a), r * std::sin(a), z};
  };
  const double rz[3][2] = {{0.012, 0.0}, {0.06, 0.06}, {0.06, 0.1}};
  for (int part = 0; part < 2; ++part)
    for (int k = 0; k < nseg; ++k) {
      const Vec3 p0 = ring(rz[part][0], rz[part][1], k), p1 = ring(rz[part][0], rz[part][1], k + 1);
      const Vec3 q0 = ring(rz[part + 1][0], rz[part + 1][1], k), q1 = ring(rz[part + 1][0], rz[part + 1][1], k + 1);
      tris.push_back({p0, p1, q1});
      tris.push_back({p0, q1, q0});
    }
  return TriangleMesh(tris);
}

// The bins keep a triangle only where the criterion may pass: the lists are still those of testing
// every triangle, also for particles at the criterion's bounds (a plane or edge distance of the reach,
// give or take an ulp), and far fewer triangles are tested than the bins of the grown boxes hold.
TEST(MeshNeighbors, HopperCandidatesAtTheCriterionBoundsAreThoseOfEveryTriangle)
{
  const TriangleMesh m = hopper();
  const double r = 0.00125, s = 0.00025, reach = r + s;
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::array<double, 3>> pos;
  for (int n = 0; n < 6000; ++n)  // inside and around the hopper
    pos.push_back({0.13 * u(gen) - 0.065, 0.13 * u(gen) - 0.065, 0.11 * u(gen) - 0.005});
  for (int n = 0; n < 6000; ++n) {  // at the plane or an edge bound of a triangle
    const int t = int(u(gen) * m.size());
    double a = u(gen), b = u(gen);
    if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
    const Vec3 on = add(m.node(t, 0), add(scale(sub(m.node(t, 1), m.node(t, 0)), a), scale(sub(m.node(t, 2), m.node(t, 0)), b)));
    const int bound = n % 4;  // 0: plane, 1-3: beyond edge k (in the plane)
    const Vec3 dir = bound == 0 ? m.normal(t) : m.edge_norm(t, bound - 1);
    const double along = bound == 0 ? reach : reach + dot(sub(m.node(t, bound - 1), on), dir);
    const double f[3] = {1.0 - 1e-15, 1.0, 1.0 + 1e-15};
    const double sign = (bound == 0 && n % 8 == 4) ? -1.0 : 1.0;
    const Vec3 q = add(on, scale(dir, sign * along * f[n % 3]));
    pos.push_back({q[0], q[1], q[2]});
  }
  std::vector<const double *> x;
  for (auto &q : pos) x.push_back(q.data());
  std::vector<double> radius(pos.size(), r);
  MeshNeighbors nb;
  nb.build(m, int(pos.size()), x.data(), radius.data(), nullptr, s);
  std::size_t found = 0, grown_box = 0;
  for (int i = 0; i < int(pos.size()); ++i) {
    const Vec3 p{pos[i][0], pos[i][1], pos[i][2]};
    std::vector<int> brute;
    for (int t = 0; t < m.size(); ++t) {
      if (MeshNeighbors::in_reach(m, t, p, reach)) brute.push_back(t);
      bool in_box = true;
      for (int d = 0; d < 3; ++d) {
        const double lo = std::min({m.node(t, 0)[d], m.node(t, 1)[d], m.node(t, 2)[d]}) - reach;
        const double hi = std::max({m.node(t, 0)[d], m.node(t, 1)[d], m.node(t, 2)[d]}) + reach;
        in_box = in_box && p[d] >= lo && p[d] <= hi;
      }
      grown_box += in_box;
    }
    ASSERT_EQ(std::vector<int>(nb.begin(i), nb.begin(i) + nb.count(i)), brute) << "particle " << i;
    found += brute.size();
  }
  EXPECT_GT(found, 6000u);
  std::printf("triangles tested: %zu, in a grown box %zu, candidates %zu\n", nb.tests_performed(), grown_box, found);
  EXPECT_LT(double(nb.tests_performed()), 0.5 * double(grown_box));
}

}  // namespace
}  // namespace dembridge::mesh::test
