// Closed-form checks of Parmec's table rules (spec parmec-springs §3) and TSERIES (Q5).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <stdexcept>

#include "spring_table.h"
#include "time_series.h"

using namespace dembridge::springs;

TEST(SpringTable, InterpolatesInsideAnInterval) {
  const auto t = SpringTable::from_pairs({0.0, 0.0, 1.0, 10.0, 3.0, 14.0});
  EXPECT_DOUBLE_EQ(t.lookup(0.5).value, 5.0);
  EXPECT_DOUBLE_EQ(t.lookup(0.5).slope, 10.0);
  EXPECT_DOUBLE_EQ(t.lookup(2.0).value, 12.0);
  EXPECT_DOUBLE_EQ(t.lookup(2.0).slope, 2.0);
}

TEST(SpringTable, BreakpointSelectsTheLeftInterval) {
  const auto t = SpringTable::from_pairs({0.0, 0.0, 1.0, 10.0, 3.0, 14.0});
  EXPECT_DOUBLE_EQ(t.lookup(1.0).value, 10.0);
  EXPECT_DOUBLE_EQ(t.lookup(1.0).slope, 10.0);  // left slope at the kink
  EXPECT_DOUBLE_EQ(t.lookup(0.0).slope, 10.0);  // first breakpoint: first interval
  EXPECT_DOUBLE_EQ(t.lookup(3.0).slope, 2.0);
}

TEST(SpringTable, ExtrapolatesLinearlyOutside) {
  const auto t = SpringTable::from_pairs({0.0, 0.0, 1.0, 10.0, 3.0, 14.0});
  EXPECT_DOUBLE_EQ(t.lookup(-2.0).value, -20.0);
  EXPECT_DOUBLE_EQ(t.lookup(-2.0).slope, 10.0);
  EXPECT_DOUBLE_EQ(t.lookup(5.0).value, 18.0);
  EXPECT_DOUBLE_EQ(t.lookup(5.0).slope, 2.0);
}

TEST(SpringTable, GapTableGivesExactZeroForce) {
  // spring_contact's gap table: exactly 0 on [0, 1] so that the dashpot switches off (spec §5)
  const auto t = SpringTable::from_pairs({0.0, 0.0, 1.0, 0.0, 2.0, 1e7});
  EXPECT_EQ(t.lookup(0.3).value, 0.0);
  EXPECT_EQ(t.lookup(1.0).value, 0.0);
  EXPECT_EQ(t.lookup(-5.0).value, 0.0);
  EXPECT_DOUBLE_EQ(t.lookup(1.5).value, 5e6);
}

TEST(SpringTable, ZeroTableIsIdenticallyZero) {
  const auto t = SpringTable::zero();
  for (double s : {-1e300, -1.0, 0.0, 3.0, 1e300}) {
    EXPECT_EQ(t.lookup(s).value, 0.0);
    EXPECT_EQ(t.lookup(s).slope, 0.0);
  }
}

TEST(SpringTable, LookupByForceInvertsAnIncreasingCurve) {
  const auto u = SpringTable::from_pairs({-0.1, -4000.0, 0.0, 0.0, 0.1, 4000.0, 0.3, 5000.0});
  EXPECT_DOUBLE_EQ(u.lookup_by_force(2000.0).at, 0.05);
  EXPECT_DOUBLE_EQ(u.lookup_by_force(2000.0).slope, 40000.0);
  EXPECT_DOUBLE_EQ(u.lookup_by_force(4500.0).at, 0.2);
  EXPECT_DOUBLE_EQ(u.lookup_by_force(4500.0).slope, 5000.0);
  EXPECT_DOUBLE_EQ(u.lookup_by_force(4000.0).slope, 40000.0);  // left interval in the force column
  EXPECT_DOUBLE_EQ(u.lookup_by_force(7000.0).at, 0.7);          // extrapolated
  EXPECT_DOUBLE_EQ(u.lookup_by_force(-8000.0).at, -0.2);
}

TEST(SpringTable, MaxAbsSlope) {
  EXPECT_DOUBLE_EQ(SpringTable::from_pairs({-1, 1e7, 0, 0, 1, 0}).max_abs_slope(), 1e7);
  EXPECT_DOUBLE_EQ(SpringTable::from_pairs({-1, -8e5, 1, 8e5}).max_abs_slope(), 8e5);
}

TEST(SpringTable, RejectsOddLengthShortAndNonIncreasingTables) {
  EXPECT_THROW(SpringTable::from_pairs({0.0, 1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(SpringTable::from_pairs({0.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(SpringTable::from_pairs({0.0, 1.0, 0.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(SpringTable::from_pairs({0.0, 1.0, 1.0, 2.0, 0.5, 3.0}), std::invalid_argument);
  EXPECT_THROW(SpringTable::from_pairs({-INFINITY, 0.0, INFINITY, 0.0}), std::invalid_argument);
  EXPECT_THROW(SpringTable::from_pairs({0.0, NAN, 1.0, 0.0}), std::invalid_argument);
  try {
    SpringTable::from_pairs({0.0, 1.0, 2.0}, "SPRING 7 unload");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("SPRING 7 unload"), std::string::npos);
  }
}

TEST(TimeSeries, ClampedForGravityButExtrapolatedAsOffset) {
  const auto ts = TimeSeries::from_pairs({0, 0, 5, 0, 10, 1, 15, 1});
  EXPECT_DOUBLE_EQ(ts.value_clamped(7.5), 0.5);
  EXPECT_DOUBLE_EQ(ts.value_clamped(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(ts.value_clamped(20.0), 1.0);
  const auto r = TimeSeries::from_pairs({0, 0, 1, 2});
  EXPECT_DOUBLE_EQ(r.value_clamped(3.0), 2.0);
  EXPECT_DOUBLE_EQ(r.as_table().lookup(3.0).value, 6.0);  // Q5: offset curves extrapolate linearly
  EXPECT_DOUBLE_EQ(r.as_table().lookup(-1.0).value, -2.0);
}

TEST(TimeSeries, ConstantCannotBeAnOffset) {
  const auto c = TimeSeries::constant(3.0);
  EXPECT_DOUBLE_EQ(c.value_clamped(100.0), 3.0);
  EXPECT_THROW(c.as_table(), std::invalid_argument);
}
