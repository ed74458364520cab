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
  // Node kinematics (global frame) for the wire.
  NodeState node_of(std::size_t i, const BodyState& b, std::uint32_t label) const;

 private:
  OscillatorParameters p_;
  std::vector<BodyState> state_;
};

}  // namespace dembridge::mbdyn::testpeer
