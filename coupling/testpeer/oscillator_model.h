// The small MBDyn model the test peer integrates: N point masses m (plus optional gravity), each
// also spinning about the global z axis with inertia J. Forces and the z moment come from the
// coupled peer, so e.g. a spring on the peer side makes each node a harmonic oscillator.
// Time integration is the trapezoidal rule (Newmark average acceleration), second order.
#pragma once

#include <vector>

#include "testpeer_wire.h"

namespace dembridge::mbdyn::testpeer {

struct BodyState {
  V3 x{}, v{}, a{};
  double theta = 0, theta_dot = 0, theta_ddot = 0;  // spin about global z
};

struct OscillatorParameters {
  double mass = 1.0;
  double inertia = 1.0;
  V3 gravity{0, 0, 0};
  std::vector<BodyState> initial;  // one per node
  std::vector<double> tilt;        // per node: R = Rz(theta) * Rx(tilt), so all 3 axes vary
  std::vector<V3> offset;          // per node, node frame: MBDyn's `offset` of the point
};

class OscillatorModel {
 public:
  explicit OscillatorModel(const OscillatorParameters& p);

  std::size_t size() const { return state_.size(); }
  const std::vector<BodyState>& state() const { return state_; }
  // Accelerations from loads on the current state (the t0 "initial derivatives").
  void set_loads_at_current_state(const std::vector<V3>& force, const std::vector<double>& moment_z);
  // MBDyn's predictor: step 1 repeats the initial state (spec §5), later a Taylor extrapolation.
  std::vector<BodyState> predict(double dt, bool first_step) const;
  // Trapezoidal step from the converged state with the given end-of-step loads.
  std::vector<BodyState> step(double dt, const std::vector<V3>& force, const std::vector<double>& moment_z) const;
  void accept(const std::vector<BodyState>& s) { state_ = s; }
  // Kinematics of node i's point (global frame) for the wire, at its offset (spec §4.3):
  // x = x_n + R o, v = v_n + w x R o, a = a_n + wdot x R o + w x (w x R o); R, w, wdot = node's.
  NodeState point_of(std::size_t i, const BodyState& b, std::uint32_t label) const;
  // z moment on the node from a load (f, m) at the point: m + (R o) x f, with R o taken at the
  // pose b the load was computed for (spec §4.3).
  double node_moment_z(std::size_t i, const BodyState& b, const V3& f, const V3& m) const;

 private:
  OscillatorParameters p_;
  std::vector<BodyState> state_;
};

}  // namespace dembridge::mbdyn::testpeer
