// The insertion kernels against closed forms and published values.
#include "discrete_distribution.h"
#include "insert_keywords.h"
#include "overlap_grid.h"
#include "park_miller.h"
#include "region_sampling.h"
#include "restart_record.h"
#include "seed_rule.h"
#include "stream_insertion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

using namespace dembridge::insertion;

TEST(ParkMiller, PublishedCheckValue)
{
  // Park & Miller (1988): from seed 1, the 10000th value of the minimal standard is 1043618065.
  ParkMiller rng(1);
  rng.skip(10000);
  EXPECT_EQ(rng.state(), 1043618065);
  // uniform() is state / (2^31 - 1)
  ParkMiller one(1);
  EXPECT_EQ(one.uniform(), 16807.0 / 2147483647.0);
}

TEST(ParkMiller, GaussianHasUnitVariance)
{
  ParkMiller rng(15485863);
  double s = 0, s2 = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double g = rng.gaussian();
    s += g;
    s2 += g * g;
  }
  EXPECT_NEAR(s / n, 0.0, 0.01);
  EXPECT_NEAR(s2 / n, 1.0, 0.01);
}

// A stream restored from its saved state (taken between the two values of a Gaussian pair) draws what
// the uninterrupted stream draws; a state no stream reaches is refused.
TEST(ParkMiller, RestoredStreamContinuesTheSameDraws)
{
  using dembridge::insertion::ParkMiller;
  ParkMiller a(32452843);
  a.skip(17);
  a.gaussian();
  const auto saved = a.saved();
  ParkMiller b(15485863);
  b.restore(saved);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(a.gaussian(), b.gaussian());
    EXPECT_EQ(a.uniform(), b.uniform());
  }
  EXPECT_THROW(b.restore({0., 0., 0.}), std::invalid_argument);
  EXPECT_THROW(b.restore({2147483647., 0., 0.}), std::invalid_argument);
  EXPECT_THROW(b.restore({12.5, 0., 0.}), std::invalid_argument);
}

// The record round-trips through the bytes LAMMPS hands back; another kind or a short record is refused.
TEST(RestartRecord, RoundTripAndRefusals)
{
  using namespace dembridge::insertion;
  ParkMiller rng(49979687);
  rng.gaussian();
  RestartWriter w(7.);
  w.put(3.25);
  w.put(rng);
  char *bytes = nullptr;
  size_t len = 0;
  FILE *f = open_memstream(&bytes, &len);
  w.write(f);
  std::fclose(f);
  int size = 0;
  std::memcpy(&size, bytes, sizeof(int));
  ASSERT_EQ(size_t(size) + sizeof(int), len);
  const char *buf = bytes + sizeof(int);
  RestartReader r(buf, 7.);
  EXPECT_EQ(r.get(), 3.25);
  ParkMiller back;
  r.get(back);
  EXPECT_EQ(back.gaussian(), rng.gaussian());
  EXPECT_THROW(r.get(), std::invalid_argument);
  EXPECT_THROW(RestartReader(buf, 8.), std::invalid_argument);
  std::free(bytes);
}

TEST(SeedRule, PrimesAbove10000Only)
{
  EXPECT_EQ(parse_seed("15485863"), 15485863);
  EXPECT_THROW(parse_seed("7919"), std::invalid_argument);       // prime but small
  EXPECT_THROW(parse_seed("1009"), std::invalid_argument);       // the insert/stream doc's "> 1000"
  EXPECT_THROW(parse_seed("15485864"), std::invalid_argument);   // even
  EXPECT_THROW(parse_seed("2147483659"), std::invalid_argument); // > INT_MAX
  EXPECT_THROW(parse_seed("12x"), std::invalid_argument);
  EXPECT_TRUE(is_prime(2147483647));
}

TEST(DiscreteDistribution, MassToNumberFractions)
{
  // radii 1 and 2, same density: masses 1:8; mass fractions 0.5/0.5 -> number fractions 8/9, 1/9
  std::vector<SphereTemplate> t = {{1, 1.0, 1.0}, {1, 2.0, 1.0}};
  DiscreteDistribution d(t, {0.5, 0.5}, true);
  EXPECT_NEAR(d.number_fractions()[0], 8.0 / 9.0, 1e-15);
  EXPECT_NEAR(d.number_fractions()[1], 1.0 / 9.0, 1e-15);
  EXPECT_FALSE(d.normalised());
  EXPECT_EQ(d.order(), (std::vector<int>{1, 0}));  // large first
  DiscreteDistribution n(t, {1.0, 3.0}, false);
  EXPECT_TRUE(n.normalised());
  EXPECT_DOUBLE_EQ(n.number_fractions()[1], 0.75);
  EXPECT_NEAR(n.vol_expect(), (0.25 * 1 + 0.75 * 8) * 4. * M_PI / 3., 1e-12);
}

TEST(DiscreteDistribution, ExactCountsTruncateThenRemainder)
{
  std::vector<SphereTemplate> t = {{1, 1.0, 1.0}, {1, 2.0, 1.0}};
  DiscreteDistribution d(t, {0.3, 0.7}, false);
  ParkMiller rng(32452843);
  const auto list = d.draw_list(10, true, rng);  // 3 + 7 exactly: no draw
  EXPECT_EQ(rng.state(), 32452843);
  ASSERT_EQ(list.size(), 10u);
  EXPECT_EQ(std::count(list.begin(), list.end(), 1), 7);
  EXPECT_EQ(list.front(), 1);  // large particles first
  const auto odd = d.draw_list(11, true, rng);  // 3.3 + 7.7: one gap, given by one draw
  EXPECT_EQ(odd.size(), 11u);
  EXPECT_NE(rng.state(), 32452843);
}

TEST(OverlapGrid, SameAnswerAsAllPairs)
{
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  OverlapGrid g(lo, hi, 0.2);
  std::vector<double> xs;
  ParkMiller rng(15485867);
  for (int i = 0; i < 300; ++i) {
    double x[3] = {rng.uniform(), rng.uniform(), rng.uniform()};
    g.add(x, 0.1);
    xs.insert(xs.end(), x, x + 3);
  }
  for (int k = 0; k < 2000; ++k) {
    double y[3] = {rng.uniform() * 1.2 - 0.1, rng.uniform() * 1.2 - 0.1, rng.uniform() * 1.2 - 0.1};
    bool brute = false;
    for (size_t i = 0; i < xs.size(); i += 3) {
      const double dx = y[0] - xs[i], dy = y[1] - xs[i + 1], dz = y[2] - xs[i + 2];
      brute = brute || dx * dx + dy * dy + dz * dz <= 0.2 * 0.2;
    }
    EXPECT_EQ(g.overlaps(y, 0.1), brute);
  }
}

namespace {
struct Ball : RegionView {
  Ball()
  {
    for (int d = 0; d < 3; ++d) {
      lo[d] = -1;
      hi[d] = 1;
    }
  }
  bool match(const double *x) const override { return x[0] * x[0] + x[1] * x[1] + x[2] * x[2] <= 1.0; }
  bool near_surface(const double *x, double cut) const override
  {
    return 1.0 - std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) < cut;
  }
};
}  // namespace

TEST(RegionSampling, MonteCarloVolumeOfABall)
{
  Ball b;
  Box box{{-2, -2, -2}, {2, 2, 2}};
  ParkMiller rng(15485863);
  const auto v = volume_mc(b, box, 100000, false, 0.0, rng);
  EXPECT_NEAR(v.global, 4. * M_PI / 3., 0.03);  // ~3 sigma of 100000 tries
  RegionSampler s(b, box);
  double p[3];
  for (int i = 0; i < 1000; ++i) {
    s.draw(p, 0.2, rng);
    EXPECT_LE(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), 0.8);
  }
  EXPECT_DOUBLE_EQ(distance_to_box_faces(box, p), std::min({p[0] + 2, 2 - p[0], p[1] + 2, 2 - p[1], p[2] + 2, 2 - p[2]}));
}

TEST(InsertKeywords, GeneralKeywordsMustComeFirst)
{
  const std::vector<std::string> ok = {"ins", "all", "insert/pack", "seed", "32452867", "distributiontemplate", "pdd",
                                       "vel", "constant", "0", "0", "-1", "insert_every", "once", "region", "r",
                                       "volumefraction_region", "0.3"};
  InsertKeywords k;
  const int i = parse_general_keywords(ok, k);
  EXPECT_EQ(ok[i], "region");
  EXPECT_EQ(k.insert_every, 0);
  EXPECT_EQ(k.vel.v[2], -1.0);
  PackKeywords p;
  parse_pack_keywords(ok, i, p);
  EXPECT_EQ(p.volumefraction, 0.3);
  std::vector<std::string> late = ok;
  late.insert(late.end(), {"all_in", "yes"});
  InsertKeywords k2;
  PackKeywords p2;
  EXPECT_THROW(parse_pack_keywords(late, parse_general_keywords(late, k2), p2), std::invalid_argument);
}

// insert/stream's face sampling: the triangle picked by accumulated area (1 uniform), then (u,v)
// redrawn until u + v <= 1, point (1-u-v) n0 + v n1 + u n2 -- recomputed here from the raw stream.
TEST(StreamFace, DrawIsAreaPickThenRejectedBarycentric)
{
  const std::vector<Triangle> tris = {{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {{{0, 0, 0}, {0, 3, 0}, {-1, 0, 0}}}};
  StreamFace face(tris, {0.5, 1.5}, {7u, 7u});
  ParkMiller a(179424799), ref(179424799);
  for (int k = 0; k < 200; ++k) {
    double p[3];
    const int t = face.draw(a, p);
    const double r = ref.uniform() * 2.0;
    EXPECT_EQ(t, r <= 0.5 ? 0 : 1);
    double u, v;
    do {
      u = ref.uniform();
      v = ref.uniform();
    } while (u + v > 1);
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(p[c], (1. - u - v) * tris[t][0][c] + v * tris[t][1][c] + u * tris[t][2][c]);
  }
}

TEST(StreamFace, SegmentDistanceAndBoxTest)
{
  const double a[3] = {0, 0, 0}, b[3] = {2, 0, 0};
  const double p1[3] = {1, 3, 4}, p2[3] = {5, 4, 0};
  EXPECT_DOUBLE_EQ(distance_to_segment(p1, a, b), 5.0);
  EXPECT_DOUBLE_EQ(distance_to_segment(p2, a, b), 5.0);  // beyond the end: to the end point
  const Box box{{0, 0, 0}, {1, 1, 1}};
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 0.5, 0.5};
  EXPECT_TRUE(in_box(box, lo));
  EXPECT_FALSE(in_box(box, hi));  // LIGGGHTS's sub-domain test is half-open
}

// parallel yes: the drawn depths are bounded by the box corners' depths behind the face that lie inside
// (0, L); a box that holds the whole extrusion volume leaves [0, L] (the same as parallel no).
TEST(StreamSettings, ParallelNarrowsTheDepthsToTheBox)
{
  StreamSettings s{};
  s.normal[2] = -1.0;  // particles move down; the extrusion volume lies above the face at z = 1
  s.extrude_length = 0.5;
  const double p_ref[3] = {0, 0, 1};
  s.box = Box{{-1, -1, -2}, {1, 1, 3}};
  narrow_to_box(s, p_ref);
  EXPECT_EQ(s.extrude_min, 0.0);
  EXPECT_EQ(s.extrude_max, 0.5);
  s.box = Box{{-1, -1, -2}, {1, 1, 1.25}};  // the top cuts the volume at depth 0.25
  narrow_to_box(s, p_ref);
  EXPECT_EQ(s.extrude_min, 0.0);
  EXPECT_EQ(s.extrude_max, 0.25);
  s.box = Box{{-1, -1, 1.125}, {1, 1, 3}};  // the bottom starts at depth 0.125, the top is beyond L
  narrow_to_box(s, p_ref);
  EXPECT_EQ(s.extrude_min, 0.125);
  EXPECT_EQ(s.extrude_max, 0.5);
  StreamKeywords sk;
  parse_stream_keywords({"ins", "all", "insert/stream", "insertion_face", "f", "extrude_length", "0.5", "parallel",
                         "yes"},
                        3, sk);
  EXPECT_TRUE(sk.parallel);
}

TEST(InsertKeywords, SetPropertyNameAndValue)
{
  const std::vector<std::string> a = {"ins", "all", "insert/pack", "seed", "32452867", "distributiontemplate", "pdd",
                                      "set_property", "tracer", "7.25", "insert_every", "once", "region", "r"};
  InsertKeywords k;
  EXPECT_EQ(a[parse_general_keywords(a, k)], "region");
  EXPECT_EQ(k.set_property, "tracer");
  EXPECT_EQ(k.set_property_value, 7.25);
}
