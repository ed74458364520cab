// Bad input, one test per rule (issue 7 acceptance D): std::invalid_argument naming the cause.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "torsion_frame.h"
#include "torsion_law.h"
#include "unspring_rule.h"

namespace dt = dembridge::torsion;
using dembridge::springs::SpringTable;
using dembridge::springs::TimeSeries;

namespace {
template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no exception)";
}
#define EXPECT_INVALID(stmt, text) EXPECT_NE(message_of([&] { stmt; }).find(text), std::string::npos) << message_of([&] { stmt; })

dt::UnspringRule rule() {
  dt::UnspringRule r;
  r.tsprings = {0, 1};
  r.msprings = {1, 2};
  r.max = 10.0;
  return r;
}
std::map<int, int> codes() { return {{0, -3}, {1, -3}, {2, -3}, {3, -1}, {4, -3}}; }
}  // namespace

TEST(TorsionValidation, NonOrthogonalDirections) {
  EXPECT_INVALID(dt::reference_frame({0, 0, 1}, {0.1, 0, 1}), "zdir and xdir must be orthogonal");
  // Q10: a negative dot product is rejected too (Parmec lets it pass)
  EXPECT_INVALID(dt::reference_frame({0, 0, 1}, {1, 0, -0.5}), "must be orthogonal");
  EXPECT_INVALID(dt::reference_frame({0, 0, 0}, {1, 0, 0}), "zdir must be a non-zero");
}

TEST(TorsionValidation, UnknownConeName) {
  EXPECT_INVALID(dt::parse_cone({"roll", "tilt"}), "unknown cone name 'tilt'");
  EXPECT_INVALID(dt::parse_cone({"roll"}), "cone must name 2 or 3");
  EXPECT_INVALID(dt::parse_cone({"roll", "roll"}), "given twice");
}

TEST(TorsionValidation, ConeWithoutItsLeadingCurve) {
  const SpringTable k = SpringTable::from_pairs({-1, 1, 1, -1});
  dt::TorsionLaw law;
  law.cone = dt::Cone::PitchYaw;
  law.axis[dt::kRoll].spring = &k;  // roll is not the leading axis of (pitch, yaw)
  law.axis[dt::kYaw].spring = &k;
  EXPECT_INVALID(law.validate(), "give kpitch or dpitch");
  law.axis[dt::kPitch].ratio = 0.5;  // a damper alone is enough
  EXPECT_NO_THROW(law.validate());
}

TEST(TorsionValidation, DamperTableAndRatioTogether) {
  const SpringTable d = SpringTable::from_pairs({-1, 1, 1, -1});
  dt::TorsionLaw law;
  law.axis[dt::kYaw].damper = &d;
  law.axis[dt::kYaw].ratio = 0.1;
  EXPECT_INVALID(law.validate(), "dyaw is either a table or a critical damping ratio");
  law.axis[dt::kYaw].damper = nullptr;
  law.axis[dt::kYaw].ratio = -0.1;
  EXPECT_INVALID(law.validate(), "must be finite and >= 0");
}

TEST(UnspringValidation, LimitsMinNotBelowMax) {
  auto r = rule();
  r.min = 10.0;
  EXPECT_INVALID(r.validate(3), "UNSPRING #3: limits must satisfy min < max");
  r.min = 11.0;
  EXPECT_INVALID(r.validate(3), "min < max");
}

TEST(UnspringValidation, SpringListedTwiceInMsprings) {
  auto r = rule();
  r.msprings = {1, 2, 1};
  EXPECT_INVALID(r.validate(0), "UNSPRING #0: spring 1 listed twice in msprings");
}

TEST(UnspringValidation, ActivatingAnActiveSpring) {
  auto r = rule();
  r.activate = {4};
  auto c = codes();
  EXPECT_INVALID(dt::register_rule(r, 1, c), "UNSPRING #1: spring 4 in activate is already active");
  r.activate = {3};
  c = codes();
  EXPECT_NO_THROW(dt::register_rule(r, 1, c));
  EXPECT_EQ(c[1], -2);
  EXPECT_EQ(c[2], -2);
  EXPECT_EQ(c[3], -1);  // activated only at the trigger
}

TEST(UnspringValidation, UnknownSpringIds) {
  auto c = codes();
  auto r = rule();
  r.tsprings = {0, 9};
  EXPECT_INVALID(dt::register_rule(r, 2, c), "unknown spring 9 in tsprings");
  r = rule();
  r.msprings = {7};
  EXPECT_INVALID(dt::register_rule(r, 2, c), "unknown spring 7 in msprings");
  r = rule();
  r.activate = {8};
  EXPECT_INVALID(dt::register_rule(r, 2, c), "unknown spring 8 in activate");
}

TEST(UnspringValidation, MspringAlreadyManagedOrInactive) {
  auto c = codes();
  auto r = rule();
  dt::register_rule(r, 0, c);
  EXPECT_INVALID(dt::register_rule(r, 1, c), "already managed by another UNSPRING");
  r.msprings = {3};
  EXPECT_INVALID(dt::register_rule(r, 1, c), "spring 3 in msprings is inactive");
}

TEST(UnspringValidation, UnknownOrBadUnloadTseries) {
  const TimeSeries good = TimeSeries::from_pairs({0.0, 0.0, 1.0, 1e4});
  const TimeSeries flat = TimeSeries::from_pairs({0.0, 0.0, 1.0, 0.0});
  const TimeSeries constant = TimeSeries::constant(1.0);
  auto find = [&](int id) -> const TimeSeries* {
    if (id == 0) return &good;
    if (id == 1) return &flat;
    if (id == 2) return &constant;
    return nullptr;
  };
  auto r = rule();
  r.unload = 5;
  EXPECT_INVALID(dt::check_unload_curves(r, 4, find), "UNSPRING #4: unknown unload TSERIES 5");
  r.unload = 1;
  EXPECT_INVALID(dt::check_unload_curves(r, 4, find), "must be strictly increasing");
  r.unload = 2;
  EXPECT_INVALID(dt::check_unload_curves(r, 4, find), "at least two points");
  r.unload = 0;
  r.unload_by_spring = {{2, 6}};
  EXPECT_INVALID(dt::check_unload_curves(r, 4, find), "unknown unload TSERIES 6");
  r.unload_by_spring = {{2, 0}};
  EXPECT_NO_THROW(dt::check_unload_curves(r, 4, find));
}

TEST(UnspringValidation, OtherRules) {
  auto r = rule();
  r.tsprings.clear();
  EXPECT_INVALID(r.validate(0), "tsprings must be non-empty");
  r = rule();
  r.nsteps = 0;
  EXPECT_INVALID(r.validate(0), "nsteps must be >= 1");
  r = rule();
  r.nfreq = 0;
  EXPECT_INVALID(r.validate(0), "nfreq must be >= 1");
  r = rule();
  r.unload_by_spring = {{0, 1}};  // spring 0 is a tspring only
  EXPECT_INVALID(r.validate(0), "not in msprings");
  EXPECT_INVALID(dt::parse_entity("STRESS"), "unknown entity 'STRESS'");
  EXPECT_INVALID(dt::parse_operator("AVG"), "unknown operator 'AVG'");
  EXPECT_EQ(dt::parse_entity("FF"), dt::Entity::FF);
  EXPECT_EQ(dt::parse_operator("MIN"), dt::Operator::Min);
}
