// Closed-form checks of the torsion kernel pieces (spec §7, §14): frame (Q10), co-rotation, sign
// convention, damper rules, axis inertias (corrected frame), outputs, two-body reaction, pack/unpack.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "axis_inertia.h"
#include "rigid_replay.h"
#include "torsion_step.h"

namespace dt = dembridge::torsion;
using dembridge::springs::SpringTable;

namespace {
dt::Mat3 rotation_z(double a) { return {std::cos(a), -std::sin(a), 0.0, std::sin(a), std::cos(a), 0.0, 0.0, 0.0, 1.0}; }
dt::Mat3 some_rotation() { return replay::to_rowmajor(replay::expmap(replay::V3(0.3, -0.7, 1.1), false)); }
}  // namespace

// Q10 fixed: both directions normalised (Parmec divides zdir twice and never xdir); y = z × x.
TEST(TorsionFrame, ReferenceDirectionsAreNormalised) {
  const dt::TorsionFrame f = dt::reference_frame({0.0, 0.0, 2.0}, {3.0, 0.0, 0.0});
  EXPECT_EQ(f.z, (dt::Vec3{0.0, 0.0, 1.0}));
  EXPECT_EQ(f.x, (dt::Vec3{1.0, 0.0, 0.0}));
  EXPECT_EQ(f.y, (dt::Vec3{0.0, 1.0, 0.0}));
}

TEST(TorsionFrame, CoRotatesWithPart1) {
  const dt::TorsionFrame r = dt::reference_frame({0.0, 0.0, 1.0}, {1.0, 0.0, 0.0});
  const dt::TorsionFrame c = dt::current_frame(r, rotation_z(M_PI / 2));
  EXPECT_NEAR(c.x[1], 1.0, 1e-15);
  EXPECT_NEAR(c.y[0], -1.0, 1e-15);
  EXPECT_NEAR(c.z[2], 1.0, 1e-15);
}

// Angle rates x·(ω1−ω2) etc.; a restoring table has negative slope; torque T_r x + T_p y + T_y z on part1;
// XDIR/ZDIR outputs are the current x and z.
TEST(TorsionStep, AngleIntegrationSignAndOutputs) {
  const SpringTable k = SpringTable::from_pairs({-1.0, 1e4, 1.0, -1e4});
  dt::TorsionLaw law;
  for (auto& a : law.axis) a.spring = &k;
  const dt::TorsionFrame r = dt::reference_frame({1.0, 0.0, 0.0}, {0.0, 1.0, 0.0});  // x=(0,1,0), y=(0,0,1), z=(1,0,0)
  dt::TorsionState st;
  dt::TorsionStepInput in;
  in.frame = dt::current_frame(r, dt::identity());
  in.relative_omega = {0.5, 2.0, -1.0};
  in.dt = 0.01;
  const auto t = dt::advance_torsion(law, st, in);
  EXPECT_DOUBLE_EQ(t.rate[0], 2.0);   // roll: x·ω
  EXPECT_DOUBLE_EQ(t.rate[1], -1.0);  // pitch: y·ω
  EXPECT_DOUBLE_EQ(t.rate[2], 0.5);   // yaw: z·ω
  EXPECT_DOUBLE_EQ(st.angle[0], 0.02);
  EXPECT_DOUBLE_EQ(st.angle[1], -0.01);
  EXPECT_DOUBLE_EQ(st.angle[2], 0.005);
  EXPECT_NEAR(t.total[0], -200.0, 1e-9);
  EXPECT_NEAR(t.total[1], 100.0, 1e-9);
  EXPECT_NEAR(t.total[2], -50.0, 1e-9);
  // on part1: −200 x + 100 y − 50 z = (−50, −200, 100)
  EXPECT_NEAR(t.on_part1[0], -50.0, 1e-9);
  EXPECT_NEAR(t.on_part1[1], -200.0, 1e-9);
  EXPECT_NEAR(t.on_part1[2], 100.0, 1e-9);
  EXPECT_EQ(st.xdir, in.frame.x);
  EXPECT_EQ(st.zdir, in.frame.z);
  EXPECT_EQ(st.torque_total, t.total);
  EXPECT_EQ(st.torque_spring, t.spring);
}

// The damper is off whenever the spring torque is exactly 0 (default table, dead band): spec §7.
TEST(TorsionStep, DamperOffWhenSpringTorqueIsZero) {
  const SpringTable d = SpringTable::from_pairs({-1.0, 5.0, 1.0, -5.0});
  const SpringTable dead = SpringTable::from_pairs({-1.0, 10.0, -0.5, 0.0, 0.5, 0.0, 1.0, -10.0});
  dt::TorsionLaw law;
  law.axis[dt::kRoll].damper = &d;  // no spring table: torque ≡ 0
  law.axis[dt::kPitch].spring = &dead;
  law.axis[dt::kPitch].damper = &d;
  dt::TorsionState st;
  dt::TorsionStepInput in;
  in.frame = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  in.relative_omega = {1.0, 1.0, 0.0};
  in.dt = 0.1;
  const auto t = dt::advance_torsion(law, st, in);
  EXPECT_EQ(t.total[0], 0.0);
  EXPECT_EQ(t.total[1], 0.0);  // angle 0.1 inside the dead band
  st.angle[1] = 0.7;
  const auto t2 = dt::advance_torsion(law, st, in);  // angle 0.8: spring −6, damper −5
  EXPECT_NEAR(t2.spring[1], -6.0, 1e-12);
  EXPECT_NEAR(t2.total[1], -11.0, 1e-12);
}

// Critical ratio: c = −ζ 2 sqrt(|k| I_axis) with the tangent slope k of this step.
TEST(TorsionStep, CriticalRatioUsesTangentAndAxisInertia) {
  const SpringTable k = SpringTable::from_pairs({-1.0, 400.0, 0.0, 0.0, 1.0, -100.0});
  dt::TorsionLaw law;
  law.axis[dt::kYaw].spring = &k;
  law.axis[dt::kYaw].ratio = 0.5;
  ASSERT_TRUE(law.needs_axis_inertia());
  dt::TorsionState st;
  dt::TorsionStepInput in;
  in.frame = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  in.relative_omega = {0.0, 0.0, 2.0};
  in.dt = 0.1;                       // yaw 0.2 on the slope −100 side
  in.axis_inertia = {1.0, 1.0, 4.0};
  const auto t = dt::advance_torsion(law, st, in);
  const double c = -0.5 * 2.0 * std::sqrt(100.0 * 4.0);
  EXPECT_NEAR(t.spring[2], -20.0, 1e-12);
  EXPECT_NEAR(t.total[2], -20.0 + c * 2.0, 1e-12);
}

// Corrected frame (spec §7): M = Rᵀ Λ J⁻¹ Λᵀ R; a frame fixed to an anisotropic body sees the same
// axis inertias whatever the body's rotation (Parmec's R J⁻¹ Rᵀ would not).
TEST(AxisInertia, AnisotropicBodyFrameIsCorrected) {
  const dt::Mat3 Jinv = {1.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 1.0 / 3.0};  // J = diag(1, 2, 3)
  const dt::TorsionFrame r = dt::reference_frame({0.0, 0.0, 1.0}, {1.0, 0.0, 0.0});
  for (const dt::Mat3& L : {dt::identity(), some_rotation(), rotation_z(0.4)}) {
    const dt::TorsionFrame c = dt::current_frame(r, L);
    const dt::Vec3 I = dt::axis_inertias(c, dt::spatial_inverse_inertia(L, Jinv), nullptr);
    EXPECT_NEAR(I[0], 1.0, 1e-13);
    EXPECT_NEAR(I[1], 2.0, 1e-13);
    EXPECT_NEAR(I[2], 3.0, 1e-13);
  }
  // a frame not aligned with the principal axes: x0 = (1,1,0)/√2 → 1/(x0ᵀ J⁻¹ x0)... diag of the inverse
  const dt::TorsionFrame r2 = dt::reference_frame({0.0, 0.0, 1.0}, {1.0, 1.0, 0.0});
  const dt::Vec3 I2 = dt::axis_inertias(r2, Jinv, nullptr);
  EXPECT_NEAR(I2[0], 1.5, 1e-13);  // R0ᵀ J⁻¹ R0 inverse = R0ᵀ J R0: x0ᵀ J x0 = (1 + 2)/2
  EXPECT_NEAR(I2[1], 1.5, 1e-13);
  EXPECT_NEAR(I2[2], 3.0, 1e-13);
}

// Two bodies: inverse inertias add (reduced inertia about the axis).
TEST(AxisInertia, TwoBodiesGiveReducedInertia) {
  const dt::Mat3 w1 = {0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5}, w2 = {0.25, 0, 0, 0, 0.25, 0, 0, 0, 0.25};
  const dt::Vec3 I = dt::axis_inertias({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, w1, &w2);
  for (double v : I) EXPECT_NEAR(v, 1.0 / 0.75, 1e-14);
}

// Two free bodies spun against each other about the yaw axis: the angle follows ω1 − ω2, part2 gets the
// opposite torque (total angular momentum stays 0), same discrete recurrence as one body of inertia I/2.
TEST(TorsionStep, TwoBodyReactionAndRelativeRate) {
  const double I = 2.0, k = 50.0, h = 1e-3;
  const SpringTable K = SpringTable::from_pairs({-1.0, k, 1.0, -k});
  replay::Body b1, b2;
  b1.J = b2.J = I * replay::Mat3::Identity();
  b1.W = replay::V3(0, 0, 1);
  b2.W = replay::V3(0, 0, -1);
  replay::Torsion s;
  s.part2 = 1;
  s.reference = dt::reference_frame({0, 0, 1}, {1, 0, 0});
  s.law.axis[dt::kYaw].spring = &K;
  replay::RigidReplay m({b1, b2}, {s}, h, false, false);
  double th = 0.0, w1 = 1.0, w2 = -1.0, worst = 0.0;
  for (int n = 0; n < 3000; ++n) {
    th += h * (w1 - w2);
    const double T = K.lookup(th).value;
    w1 += h * T / I;
    w2 -= h * T / I;
    m.step();
    worst = std::max({worst, std::fabs(m.springs()[0].state.angle[2] - th), std::fabs(m.bodies()[0].w(2) - w1),
                      std::fabs(m.bodies()[1].w(2) - w2)});
    EXPECT_NEAR(m.bodies()[0].t(2), -m.bodies()[1].t(2), 0.0);
  }
  EXPECT_LT(worst, 1e-13);
}

// pack/unpack: a run continued from an unpacked state equals the continuous run bitwise.
TEST(TorsionState, PackUnpackContinuesBitwise) {
  const SpringTable K = SpringTable::from_pairs({-1.0, 1e4, 1.0, -1e4});
  dt::TorsionLaw law;
  for (auto& a : law.axis) {
    a.spring = &K;
    a.ratio = 0.2;
  }
  dt::TorsionStepInput in;
  in.dt = 1e-3;
  in.axis_inertia = {3.0, 4.0, 5.0};
  auto drive = [&](dt::TorsionState& st, int n) {
    in.frame = dt::current_frame(dt::reference_frame({0, 0, 1}, {1, 0, 0}), rotation_z(0.01 * n));
    in.relative_omega = {std::sin(0.01 * n), std::cos(0.02 * n), 0.3};
    return dt::advance_torsion(law, st, in);
  };
  dt::TorsionState a, b;
  for (int n = 0; n < 50; ++n) drive(a, n);
  std::vector<double> buf(dt::TorsionState::kPackedSize, -1.0);
  a.pack(buf.data());
  b.unpack(buf.data());
  for (int n = 50; n < 120; ++n) {
    const auto ta = drive(a, n);
    const auto tb = drive(b, n);
    ASSERT_EQ(ta.on_part1, tb.on_part1);
  }
  EXPECT_EQ(a.angle, b.angle);
  EXPECT_EQ(a.torque_total, b.torque_total);
  EXPECT_EQ(a.torque_spring, b.torque_spring);
  EXPECT_EQ(a.xdir, b.xdir);
  EXPECT_EQ(a.zdir, b.zdir);
}
