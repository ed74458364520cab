// A point at an offset from its node (MBDyn `offset`, spec §4.3): the kinematics the library
// receives are those of the point, and a moment about the point is transferred to the node as
// m + (R o) x f. Free rigid motion under a constant force with zero net torque has a closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "test_support.h"

using namespace dembridge::mbdyn;
using dembridge::mbdyn::test::PeerThread;

namespace {

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

Vec3 times(const Matrix3& R, const Vec3& v) {
  Vec3 r{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r[i] += R[3 * i + k] * v[k];
  return r;
}

// R = Rz(theta) Rx(tilt), the test peer's node orientation, written out independently.
Matrix3 node_rotation(double theta, double tilt) {
  const double c = std::cos(theta), s = std::sin(theta), ct = std::cos(tilt), st = std::sin(tilt);
  return {c, -s * ct, s * st, s, c * ct, -c * st, 0, st, ct};
}

}  // namespace

TEST(OffsetPoint, PointKinematicsAndMomentTransferMatchRigidBodyClosedForm) {
  const double mass = 2.0, dt = 0.01, tilt = 0.3;
  const Vec3 offset{0.2, -0.1, 0.3}, force{1.0, -2.0, 0.5};
  NodalConfig c;
  c.num_points = 1;
  c.rotation = Rotation::Euler123;
  c.accelerations = true;
  auto pair = test::make_pair_setup(c, Coupling::Loose, "offset");
  pair.peer.steps = 100;
  pair.peer.dt = dt;
  pair.peer.model.mass = mass;
  pair.peer.model.offset = {{offset[0], offset[1], offset[2]}};
  pair.peer.model.tilt = {tilt};
  pair.peer.model.derivatives_coefficient = 0;  // MBDyn's c F momentum offset at t0 (1e-8) off
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);

  const auto b0 = testpeer::default_initial_states(1)[0];
  double worst = 0;
  for (;;) {
    const Received r = s.receive();
    if (!r.is_kinematics()) break;
    const Kinematics& k = s.kinematics();
    // Message k >= 1 carries MBDyn's crank nicolson prediction for t_k from the converged state
    // at tp = t_{k-1} (the trapezoidal rule is exact for a constant force and spin):
    // x = x(tp) + dt v(tp), v = v(tp), theta = theta(tp) + dt theta_dot. Message 0 is t0.
    const double t = r.message_index * dt;
    const double tp = r.message_index == 0 ? 0.0 : t - dt, ahead = r.message_index == 0 ? 0.0 : dt;
    const double theta = b0.theta + b0.theta_dot * t;
    const Vec3 w{0, 0, b0.theta_dot};
    const Vec3 arm = times(node_rotation(theta, tilt), offset);
    const Vec3 w_arm = cross(w, arm), w_w_arm = cross(w, w_arm);
    for (int d = 0; d < 3; ++d) {
      const double accel = force[d] / mass;
      const double x = b0.x[d] + b0.v[d] * tp + 0.5 * accel * tp * tp + ahead * (b0.v[d] + accel * tp) + arm[d];
      const double v = b0.v[d] + accel * tp + w_arm[d];
      worst = std::max({worst, std::fabs(k.x[d] - x), std::fabs(k.v[d] - v), std::fabs(k.omega[d] - w[d])});
      if (r.message_index > 0) worst = std::max(worst, std::fabs(k.a[d] - (accel + w_w_arm[d])));
    }
    const Matrix3 R = k.rotation_matrix(0);
    const Matrix3 expected = node_rotation(theta, tilt);
    for (int i = 0; i < 9; ++i) worst = std::max(worst, std::fabs(R[i] - expected[i]));

    // Force at the point, and the moment about the point that cancels its lever arm on the
    // node: the node must keep spinning freely.
    Loads loads(c);
    loads.set_force(0, force);
    const Vec3 lever = times(R, offset);
    const Vec3 m = cross(lever, force);
    loads.set_moment(0, {-m[0], -m[1], -m[2]});
    s.send_loads(loads, true);
  }
  const auto out = peer.join();
  ASSERT_EQ(out.exit_status, 0) << out.log;
  std::printf("[ offset   ] max deviation from rigid-body closed form over 101 messages: %.2e\n", worst);
  EXPECT_LT(worst, 1e-11);
  EXPECT_NEAR(out.trajectory.back().bodies[0].theta, b0.theta + b0.theta_dot * 1.0, 1e-12);
}

TEST(OffsetPoint, UncompensatedForceAtTheOffsetSpinsTheNode) {
  // Control for the test above: the same force without the compensating moment must change
  // the spin rate (sign: (R o) x f).
  const Vec3 offset{0.5, 0, 0}, force{0, 1.0, 0};
  NodalConfig c;
  c.num_points = 1;
  c.rotation = Rotation::OrientationMatrix;
  auto pair = test::make_pair_setup(c, Coupling::Loose, "offset-spin");
  pair.peer.steps = 10;
  pair.peer.model.offset = {{offset[0], offset[1], offset[2]}};
  pair.peer.model.tilt = {0.0};
  pair.peer.model.initial = testpeer::default_initial_states(1);
  pair.peer.model.initial[0].theta = 0;
  pair.peer.model.initial[0].theta_dot = 0;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  while (s.receive().is_kinematics()) {
    Loads loads(c);
    loads.set_force(0, force);
    s.send_loads(loads, true);
  }
  const auto out = peer.join();
  ASSERT_EQ(out.exit_status, 0) << out.log;
  // Torque 0.5 about +z on inertia 1: theta_dot ~ 0.5 t > 0 (to first order, the arm turns).
  EXPECT_NEAR(out.trajectory.back().bodies[0].theta_dot, 0.5 * 10 * 1e-3, 1e-4);
}
