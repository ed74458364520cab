// Closed-form checks of the spring law pieces the oracle cases do not isolate: state codes, UNSPRING
// unloading, quirk fixes (Q6, Q9), the dashpot switch, geometry modes, validation and state packing.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "elastic_response.h"
#include "spring_friction.h"
#include "spring_geometry.h"
#include "spring_law.h"
#include "spring_state.h"
#include "spring_step.h"

using namespace dembridge::springs;

namespace {

const SpringTable kLinear = SpringTable::from_pairs({-1.0, -100.0, 1.0, 100.0});  // k = 100
const SpringTable kDashpot = SpringTable::from_pairs({-1.0, -10.0, 1.0, 10.0});   // c = 10

// elastic_step as advance_spring uses it: the returned force becomes the next step's f_prev
double elastic(const SpringLaw& law, SpringState& st, double stroke, double offset = 0.0) {
  return st.force_elastic = elastic_step(law, st, stroke, offset);
}

SpringFrame axial(double len, double velocity, Vec3 ut = {}) {
  SpringFrame f;
  f.len = len;
  f.z = {1.0, 0.0, 0.0};
  f.velocity = velocity;
  f.u_tangential = ut;
  f.distance = std::fabs(len);
  return f;
}

}  // namespace

TEST(SpringLaw, LinearSpringWithTableDashpot) {
  SpringLaw law;
  law.spring = &kLinear;
  law.dashpot = &kDashpot;
  SpringState st = SpringState::initial(law);
  SpringStepInput in;
  in.stroke0 = 1.0;
  const SpringForce f = advance_spring(law, st, axial(1.25, 0.5), in);
  EXPECT_DOUBLE_EQ(f.elastic, 25.0);
  EXPECT_DOUBLE_EQ(f.total, 30.0);
  EXPECT_DOUBLE_EQ(f.damping, 10.0);
  EXPECT_DOUBLE_EQ(f.on_part1[0], 30.0);  // tension pulls part1 towards part2 along +z
  EXPECT_DOUBLE_EQ(st.stroke, 0.25);
  EXPECT_DOUBLE_EQ(st.tangent_stiffness, 100.0);
}

TEST(SpringLaw, DashpotIsOffWhileTheElasticForceIsExactlyZero) {
  const SpringTable gap = SpringTable::from_pairs({0, 0, 1, 0, 2, 1e7});
  SpringLaw law;
  law.spring = &gap;
  law.dashpot = &kDashpot;
  SpringState st = SpringState::initial(law);
  SpringStepInput in;
  EXPECT_EQ(advance_spring(law, st, axial(0.5, 3.0), in).total, 0.0);
  EXPECT_DOUBLE_EQ(advance_spring(law, st, axial(1.5, 0.1), in).total, 5e6 + 1.0);
}

TEST(SpringLaw, CriticalRatioDashpotUsesTangentStiffnessAndEquivalentMass) {
  SpringLaw law;
  law.spring = &kLinear;
  law.damping_ratio = 0.5;
  SpringState st = SpringState::initial(law);
  SpringStepInput in;
  in.equivalent_mass = 4.0;
  const SpringForce f = advance_spring(law, st, axial(0.1, -2.0), in);
  EXPECT_DOUBLE_EQ(f.damping, 0.5 * 2.0 * std::sqrt(100.0 * 4.0));  // c = zeta 2 sqrt(|k_tan| m_eq) = 20
  EXPECT_DOUBLE_EQ(f.total, 10.0 - 40.0);
}

TEST(SpringLaw, InactiveSpringTracksStrokeButGivesNoForce) {
  SpringLaw law;
  law.spring = &kLinear;
  law.dashpot = &kDashpot;
  law.friction = 0.5;
  law.kskn = 1.0;
  SpringState st = SpringState::initial(law, /*inactive=*/true);
  EXPECT_EQ(st.code, kZeroForce);
  SpringStepInput in;
  in.dt = 0.1;
  const SpringForce f = advance_spring(law, st, axial(0.3, 1.0, {0.0, 2.0, 0.0}), in);
  EXPECT_EQ(f.total, 0.0);
  EXPECT_EQ(f.elastic, 0.0);
  EXPECT_EQ(st.friction_force, 0.0);
  EXPECT_DOUBLE_EQ(st.stroke, 0.3);
  EXPECT_DOUBLE_EQ(st.friction_disp[1], 0.2);  // delta reset, then left at the trial h u_t (spec §4.3)
  // activated (UNSPRING activate: -1 -> -3) it switches on from its original stroke0
  st.code = kRegular;
  EXPECT_DOUBLE_EQ(advance_spring(law, st, axial(0.3, 0.0), in).elastic, 30.0);
}

TEST(SpringLaw, UnspringUnloadReducesForceAlongTheCurveThenZeroForever) {
  const SpringTable unload = SpringTable::from_pairs({0.0, 0.0, 1.0, 1000.0});  // slope 1000
  SpringLaw law;
  law.spring = &kLinear;
  SpringState st = SpringState::initial(law);
  SpringStepInput in;
  in.unspring_unload = &unload;
  EXPECT_DOUBLE_EQ(advance_spring(law, st, axial(0.5, 0.0), in).elastic, 50.0);
  st.code = 7;  // being unloaded along TSERIES 7
  // any motion reduces |F| by |slope ds|, also motion that would load the spring further
  EXPECT_NEAR(advance_spring(law, st, axial(0.52, 0.0), in).elastic, 30.0, 1e-12);
  EXPECT_NEAR(advance_spring(law, st, axial(0.51, 0.0), in).elastic, 20.0, 1e-12);
  EXPECT_EQ(st.code, 7);
  EXPECT_EQ(advance_spring(law, st, axial(0.48, 0.0), in).elastic, 0.0);  // would cross zero
  EXPECT_EQ(st.code, kZeroForce);
  EXPECT_EQ(advance_spring(law, st, axial(0.9, 0.0), in).elastic, 0.0);
}

TEST(SpringLaw, UnspringWithoutCurveRemovesInstantly) {
  SpringLaw law;
  law.spring = &kLinear;
  SpringState st = SpringState::initial(law);
  st.code = 3;
  SpringStepInput in;
  EXPECT_EQ(advance_spring(law, st, axial(0.5, 0.0), in).total, 0.0);
  EXPECT_EQ(st.code, kZeroForce);
}

// Backbone [-1,-3000 .. 1,5000] with kinks at +-0.1, unload slope 40000, ylim (-1000, 1500).
TEST(UnloadState, ReloadingAlongUnloadCurveReportsUnloadSlope) {
  const SpringTable spring = SpringTable::from_pairs({-1.0, -3000.0, -0.1, -1500.0, 0.0, 0.0, 0.1, 2000.0, 1.0, 5000.0});
  const SpringTable unload = SpringTable::from_pairs({-0.1, -4000.0, 0.0, 0.0, 0.1, 4000.0});
  SpringLaw law;
  law.spring = &spring;
  law.unload = &unload;
  law.ylim_comp = -1000.0;
  law.ylim_tens = 1500.0;
  law.validate();
  SpringState st = SpringState::initial(law);
  EXPECT_DOUBLE_EQ(elastic(law, st, 0.05), 1000.0);  // elastic
  EXPECT_FALSE(st.yielded);
  EXPECT_DOUBLE_EQ(elastic(law, st, 0.1), 2000.0);  // > 1500: yields, backbone value kept
  EXPECT_TRUE(st.yielded);
  EXPECT_DOUBLE_EQ(st.stroke_tens, 0.1);
  EXPECT_DOUBLE_EQ(st.yield_comp, 0.0);  // compression limit reset on tensile yield
  const double fmax = 2000.0 + 3000.0 / 0.9 * 0.1;
  EXPECT_NEAR(elastic(law, st, 0.2), fmax, 1e-9);  // loading on the backbone from st
  EXPECT_NEAR(st.yield_tens, fmax, 1e-9);
  EXPECT_NEAR(elastic(law, st, 0.19), fmax - 400.0, 1e-9);  // unloading: slope 40000
  EXPECT_TRUE(st.unloading);
  EXPECT_NEAR(elastic(law, st, 0.195), fmax - 200.0, 1e-9);  // re-loading on the unload curve
  EXPECT_TRUE(st.unloading);
  EXPECT_DOUBLE_EQ(st.tangent_stiffness, 40000.0);  // Q6 fixed (Parmec keeps a stale value here)
}

TEST(UnloadState, UnloadingThroughZeroEntersTheCompressionBackbone) {
  const SpringTable spring = SpringTable::from_pairs({-1.0, -1000.0, 1.0, 1000.0});  // k = 1000
  const SpringTable unload = SpringTable::from_pairs({-1.0, -10000.0, 1.0, 10000.0});  // k_u = 10000
  SpringLaw law;
  law.spring = &spring;
  law.unload = &unload;
  SpringState st = SpringState::initial(law);  // ylim (0, 0): yields at the first non-zero force
  elastic(law, st, 0.1);  // 100, yielded in tension, yc = 0
  EXPECT_TRUE(st.yielded);
  // ds = -0.02: f = 100 - 200 < 0 crosses zero: exact unload value at at + ds = 0.01 - 0.02 -> -100;
  // below yc = 0, so the compression backbone continues from sc = 0: sc = -0.02 -> -20
  EXPECT_DOUBLE_EQ(elastic(law, st, 0.08), -20.0);
  EXPECT_DOUBLE_EQ(st.stroke_comp, -0.02);
  EXPECT_FALSE(st.unloading);
}

TEST(UnloadState, OffsetShiftsTheBackboneOnlyBeforeYield) {
  const SpringTable spring = SpringTable::from_pairs({-1.0, -1000.0, 1.0, 1000.0});
  const SpringTable unload = SpringTable::from_pairs({-1.0, -10000.0, 1.0, 10000.0});
  SpringLaw law;
  law.spring = &spring;
  law.unload = &unload;
  law.ylim_comp = -500.0;
  law.ylim_tens = 500.0;
  SpringState st = SpringState::initial(law);
  EXPECT_DOUBLE_EQ(elastic(law, st, 0.3, 0.1), 200.0);  // table(s - o)
  EXPECT_DOUBLE_EQ(elastic(law, st, 0.7, 0.1), 600.0);  // > 500: yields; st = s = 0.7 (without offset)
  EXPECT_DOUBLE_EQ(st.stroke_tens, 0.7);
  EXPECT_DOUBLE_EQ(elastic(law, st, 0.8, 0.5), 800.0);  // backbone at st = 0.8, offset ignored
}

TEST(Friction, SlidingOpposesRelativeMotionWithMuTimesTotalForce) {
  SpringState st;
  const Vec3 f = friction_step(0.3, 0.0, st, {3.0, 4.0, 0.0}, -10.0, -8.0, 0.0, 0.1);
  EXPECT_DOUBLE_EQ(f[0], 0.3 * 10.0 * 0.6);  // along u_t (velocity of point2 relative to point1)
  EXPECT_DOUBLE_EQ(f[1], 0.3 * 10.0 * 0.8);
  EXPECT_DOUBLE_EQ(st.friction_force, 3.0);
}

TEST(Friction, StickThenSlipWithTangentialSpring) {
  SpringState st;
  st.tangent_stiffness = 100.0;
  // stick: F_t = kskn k delta + kskn c u_t = 0.5*100*0.01 + 0.5*2*0.1 = 0.6 < mu |F| = 1
  Vec3 f = friction_step(0.1, 0.5, st, {0.1, 0.0, 0.0}, 10.0, 10.0, 2.0, 0.1);
  EXPECT_DOUBLE_EQ(f[0], 0.6);
  EXPECT_DOUBLE_EQ(st.friction_disp[0], 0.01);
  // slip: trial delta 0.11 -> 5.5 + 0.1 > 1: force capped, delta rescaled so that c0 |delta| = limit
  f = friction_step(0.1, 0.5, st, {1.0, 0.0, 0.0}, 10.0, 10.0, 2.0, 0.1);
  EXPECT_DOUBLE_EQ(f[0], 1.0);
  EXPECT_DOUBLE_EQ(st.friction_disp[0], 1.0 / 50.0);
}

TEST(Friction, ZeroTangentStiffnessDoesNotDivideByZero) {  // Q9 guard
  SpringState st;
  st.tangent_stiffness = 0.0;
  st.friction_disp = {0.5, 0.0, 0.0};
  const Vec3 f = friction_step(0.1, 0.5, st, {10.0, 0.0, 0.0}, 1.0, 1.0, 4.0, 0.1);
  EXPECT_DOUBLE_EQ(f[0], 0.1);
  EXPECT_DOUBLE_EQ(st.friction_disp[0], 0.5);
  EXPECT_TRUE(std::isfinite(st.friction_disp[0]));
}

TEST(SpringGeometry, DirectionModes) {
  SpringKinematics k;
  k.p = {0.0, 0.0, 0.0};
  k.q = {3.0, 4.0, 12.0};
  k.u = {1.0, 0.0, 2.0};
  const SpringFrame fol = spring_frame(DirectionMode::Follower, {}, k);
  EXPECT_DOUBLE_EQ(fol.len, 13.0);
  EXPECT_DOUBLE_EQ(fol.z[2], 12.0 / 13.0);
  EXPECT_DOUBLE_EQ(fol.velocity, (3.0 + 24.0) / 13.0);
  const SpringFrame con = spring_frame(DirectionMode::Constant, {0.0, 0.0, 1.0}, k);
  EXPECT_DOUBLE_EQ(con.len, 12.0);
  EXPECT_DOUBLE_EQ(con.velocity, 2.0);
  EXPECT_DOUBLE_EQ(con.u_tangential[0], 1.0);
  EXPECT_DOUBLE_EQ(con.distance, 13.0);  // LENGTH is always |q - p|
  const SpringFrame pla = spring_frame(DirectionMode::Planar, {0.0, 0.0, 1.0}, k);
  EXPECT_DOUBLE_EQ(pla.len, 5.0);
  EXPECT_DOUBLE_EQ(pla.z[0], 0.6);
  EXPECT_DOUBLE_EQ(pla.z[2], 0.0);
  k.normal = {0.0, 0.0, 1.0};
  const SpringFrame pln = spring_frame(DirectionMode::Plane, {}, k);
  EXPECT_DOUBLE_EQ(pln.len, -12.0);      // signed distance of point1 from the plane through q
  EXPECT_DOUBLE_EQ(pln.velocity, 2.0);   // = -d(stroke)/dt in plane mode
  SpringKinematics zero;                 // zero-length follower: no direction, no force direction
  const SpringFrame z0 = spring_frame(DirectionMode::Follower, {}, zero);
  EXPECT_EQ(z0.len, 0.0);
  EXPECT_EQ(norm(z0.z), 0.0);
}

TEST(SpringGeometry, ReferenceStrokeAndPlaneAnchor) {
  const Vec3 P1{1.0, 2.0, 3.0}, P2{4.0, 6.0, 3.0};
  EXPECT_DOUBLE_EQ(reference_stroke0(DirectionMode::Follower, {}, P1, P2), 5.0);
  EXPECT_DOUBLE_EQ(reference_stroke0(DirectionMode::Constant, {0.0, 1.0, 0.0}, P1, P2), 4.0);
  EXPECT_DOUBLE_EQ(reference_stroke0(DirectionMode::Planar, {1.0, 0.0, 0.0}, P1, P2), 4.0);
  EXPECT_DOUBLE_EQ(reference_stroke0(DirectionMode::Plane, {0.0, 0.0, 1.0}, P1, P2), 0.0);
  const Vec3 Q = plane_anchor(P1, {7.0, 7.0, 0.0}, {0.0, 0.0, 1.0});
  EXPECT_DOUBLE_EQ(Q[0], 1.0);
  EXPECT_DOUBLE_EQ(Q[1], 2.0);
  EXPECT_DOUBLE_EQ(Q[2], 0.0);
  const Vec3 u = relative_velocity({1, 0, 0}, {0, 0, 1}, {1, 0, 0}, true, {0, 2, 0}, {0, 0, 0}, {0, 0, 0});
  EXPECT_DOUBLE_EQ(u[0], -1.0);  // (v2) - (v1 + w1 x a) = (0,2,0) - (1,1,0)
  EXPECT_DOUBLE_EQ(u[1], 1.0);
  EXPECT_THROW(unit_direction({0.0, 0.0, 0.0}, "SPRING direction"), std::invalid_argument);
}

TEST(SpringLaw, ValidationNamesTheBrokenRule) {
  const SpringTable decreasing = SpringTable::from_pairs({0.0, 1.0, 1.0, 0.0});
  SpringLaw law;
  EXPECT_THROW(law.validate(), std::invalid_argument);  // no spring table
  law.spring = &kLinear;
  law.unload = &decreasing;
  EXPECT_THROW(law.validate(), std::invalid_argument);  // unload slope <= 0
  law.unload = nullptr;
  law.ylim_comp = 10.0;
  EXPECT_THROW(law.validate(), std::invalid_argument);  // ylim signs
  law.ylim_comp = 0.0;
  law.friction = -1.0;
  EXPECT_THROW(law.validate(), std::invalid_argument);
  law.friction = 0.0;
  law.kskn = -0.5;
  EXPECT_THROW(law.validate(), std::invalid_argument);
  law.kskn = 0.0;
  law.dashpot = &kDashpot;
  law.damping_ratio = 0.3;
  EXPECT_THROW(law.validate(), std::invalid_argument);  // both a table and a ratio
  law.dashpot = nullptr;
  EXPECT_NO_THROW(law.validate());
}

// Packing the state mid-history and continuing from the unpacked copy gives bitwise the same forces
// (what migration and restart rely on).
TEST(SpringState, PackUnpackContinuesBitwise) {
  const SpringTable spring = SpringTable::from_pairs({-1.0, -3000.0, -0.1, -1500.0, 0.0, 0.0, 0.1, 2000.0, 1.0, 5000.0});
  const SpringTable unload = SpringTable::from_pairs({-0.1, -4000.0, 0.0, 0.0, 0.1, 4000.0});
  SpringLaw law;
  law.spring = &spring;
  law.unload = &unload;
  law.ylim_comp = -1000.0;
  law.ylim_tens = 1500.0;
  law.dashpot = &kDashpot;
  law.friction = 0.2;
  law.kskn = 0.5;
  SpringState a = SpringState::initial(law);
  SpringStepInput in;
  in.dt = 1e-3;
  auto motion = [](int n) { return 0.3 * std::sin(0.01 * n) + 0.05 * std::sin(0.13 * n); };
  for (int n = 0; n < 500; ++n) advance_spring(law, a, axial(motion(n), 0.1, {0.2, -0.1, 0.0}), in);
  EXPECT_TRUE(a.yielded);
  std::vector<double> buf(SpringState::kPackedSize, -7.0);
  a.pack(buf.data());
  SpringState b;
  b.unpack(buf.data());
  for (int n = 500; n < 1000; ++n) {
    const SpringForce fa = advance_spring(law, a, axial(motion(n), 0.1, {0.2, -0.1, 0.0}), in);
    const SpringForce fb = advance_spring(law, b, axial(motion(n), 0.1, {0.2, -0.1, 0.0}), in);
    ASSERT_EQ(fa.total, fb.total) << n;
    ASSERT_EQ(fa.friction[0], fb.friction[0]) << n;
  }
  std::vector<double> pa(SpringState::kPackedSize), pb(SpringState::kPackedSize);
  a.pack(pa.data());
  b.pack(pb.data());
  EXPECT_EQ(pa, pb);
}
