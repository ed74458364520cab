// OBSTACLE triangle sets: validation and Parmec's rigid motion (point velocity + spatial angular velocity).
#include "obstacle.h"
#include "unit_square.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

using namespace dembridge::parmec_contact;
using dembridge::mesh::TriangleNodes;

TEST(Obstacle, BadTrianglesAndColoursAreRefused)
{
  std::vector<TriangleNodes> degenerate{TriangleNodes{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{2, 0, 0}}};
  EXPECT_ANY_THROW(Obstacle(degenerate, {1}));
  std::vector<TriangleNodes> nan{TriangleNodes{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, NAN, 0}}};
  EXPECT_ANY_THROW(Obstacle(nan, {1}));
  EXPECT_THROW(Obstacle(unit_square(0.0), {1}), std::invalid_argument);
  EXPECT_THROW(Obstacle(unit_square(0.0), {1, 0}), std::invalid_argument);
}

TEST(Obstacle, StaticObstacleNeverMoves)
{
  Obstacle o(unit_square(0.0), {1, 2});
  o.start(0.0, 0.1, false);
  o.advance(0.0, 0.1);
  EXPECT_EQ(o.mesh().node(0, 1)[0], 1.0);
  EXPECT_EQ(o.color(1), 2);
  const Vec3 v = o.velocity_at({0.5, 0.5, 0});
  EXPECT_EQ(v[0], 0.0);
}

TEST(Obstacle, ConstantVelocityIsAtTheParticlesHalfStep)
{
  const double h = 0.01, vz = 2.0;
  Obstacle o(unit_square(0.0), {1, 1});
  o.set_motion({0, 0, 0}, [&](double) { return Vec3{0, 0, vz}; }, nullptr);
  o.start(0.0, h, false);
  EXPECT_DOUBLE_EQ(o.mesh().node(0, 0)[2], 0.5 * h * vz);  // x_{1/2}
  double t = 0.0;
  for (int n = 0; n < 10; ++n, t += h) o.advance(t, h);
  EXPECT_NEAR(o.mesh().node(1, 2)[2], 10.5 * h * vz, 1e-15);
  EXPECT_NEAR(o.point()[2], 10.5 * h * vz, 1e-15);
}

TEST(Obstacle, ParmecStartLeadsByHalfAStep)
{
  const double h = 0.01;
  Obstacle o(unit_square(0.0), {1, 1});
  o.set_motion({0, 0, 0}, [](double t) { return Vec3{t, 0, 0}; }, nullptr);  // v = t
  o.start(0.0, h, true);
  EXPECT_DOUBLE_EQ(o.mesh().node(0, 0)[0], h * 0.5 * h);  // a full step with v(h/2)
  EXPECT_DOUBLE_EQ(o.linear()[0], 0.5 * h);
  o.advance(0.0, h);  // then steps with v(t_{n+1})
  EXPECT_DOUBLE_EQ(o.linear()[0], h);
}

TEST(Obstacle, SpinAboutThePointAndItsMaterialVelocity)
{
  const double h = 1e-3, w = 3.0;
  Obstacle o(unit_square(0.0), {1, 1});
  o.set_motion({0, 0, 0}, nullptr, [&](double) { return Vec3{0, 0, w}; });
  o.start(0.0, h, false);
  double t = 0.0;
  for (int n = 0; n < 99; ++n, t += h) o.advance(t, h);
  const double angle = 99.5 * h * w;
  const Vec3 &p = o.mesh().node(0, 1);  // was (1, 0, 0)
  EXPECT_NEAR(p[0], std::cos(angle), 1e-12);
  EXPECT_NEAR(p[1], std::sin(angle), 1e-12);
  const Vec3 v = o.velocity_at({1, 0, 0});
  EXPECT_DOUBLE_EQ(v[1], w);
  EXPECT_EQ(v[0], 0.0);
}

TEST(Obstacle, SaveAndRestoreContinueBitwise)
{
  auto motion = [](Obstacle &o) {
    o.set_motion({0.2, 0, 0}, [](double t) { return Vec3{std::sin(t), 0, 1}; }, [](double t) { return Vec3{0, t, 1}; });
  };
  Obstacle a(unit_square(0.0), {1, 1}), b(unit_square(0.0), {1, 1});
  motion(a);
  motion(b);
  const double h = 0.01;
  a.start(0, h, false);
  double t = 0;
  for (int n = 0; n < 5; ++n, t += h) a.advance(t, h);
  b.restore(a.save());
  for (int n = 0; n < 5; ++n, t += h) {
    a.advance(t, h);
    b.advance(t, h);
  }
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a.mesh().node(1, 2)[k], b.mesh().node(1, 2)[k]);
  EXPECT_EQ(a.point()[0], b.point()[0]);
}

TEST(Obstacle, ClosestPointOnTriangleMatchesASampledSearch)
{
  const Vec3 a{0, 0, 0}, b{2, 0, 0.5}, c{0.3, 1.5, -0.2};
  std::srand(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 p{4.0 * std::rand() / RAND_MAX - 1.5, 4.0 * std::rand() / RAND_MAX - 1.5, 2.0 * std::rand() / RAND_MAX - 1.0};
    const Vec3 q = closest_point_on_triangle(a, b, c, p);
    const double dq = dembridge::mesh::norm(dembridge::mesh::sub(p, q));
    double best = 1e300;
    const int n = 200;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = double(i) / n, v = double(j) / n;
        const Vec3 s{a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]), a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]),
                     a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2])};
        best = std::min(best, dembridge::mesh::norm(dembridge::mesh::sub(p, s)));
      }
    EXPECT_LE(dq, best + 1e-12);      // never farther than any sampled point
    EXPECT_GE(dq, best - 0.02);       // and as close as the sampling resolution allows
  }
}
