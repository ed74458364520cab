// The small MBDyn model the test peer integrates: N point masses m (plus optional gravity and a
// constant force), each also spinning about the global z axis with inertia J. Forces and the z
// moment come from the coupled peer, so e.g. a spring on the peer side makes each node a harmonic
// oscillator.
//
// Integrated the way MBDyn 1.7.3 integrates a dynamic structural node with `method: crank
// nicolson` (learnt from MBDyn's stepsol / strnode sources and checked against the recorded real
// runs in tests/data/mbdyn/): every degree of freedom has a position x with derivative v and a
// momentum q with derivative qp;
//   initial derivatives: qp0 = F(t0), q0 = m v0 + c qp0 (c = derivatives coefficient * dt), x0 and
//                        v0 kept (MBDyn restores the node's position and velocity);
//   predictor:           v = v_{-1}, x = x_{-1} + dt v_{-1}, qp = qp_{-1}, q = q_{-1} + dt qp_{-1};
//   corrector:           qp = F, q = q_{-1} + dt/2 (qp_{-1} + qp), v = q / m,
//                        x = x_{-1} + dt/2 (v_{-1} + v)   (the external loads have no Jacobian, so
//                        one Newton correction solves the step for given loads exactly).
// The residual whose norm MBDyn tests is (F - qp, q - m v) over every degree of freedom.
// With `multistep` (MBDyn's `method: ms, rho`, its two-step method at a constant step, not for a
// hinged body): every pair (y, y') above is predicted with MBDyn's cubic derivative predictor
//   y'_p = (-12 y_{-1} + 12 y_{-2}) / dt + 8 y'_{-1} + 5 y'_{-2},
//   y_p  = a1 y_{-1} + a2 y_{-2} + b0 y'_p + b1 y'_{-1} + b2 y'_{-2},
// and corrected with the same formula for y, with a1 = 1 - beta, a2 = beta, b0 = dt (delta + 1/2),
// b1 = dt (beta/2 + 1/2 - 2 delta), b2 = dt (beta/2 + delta), beta = (3 (1-rho)^2 + 4 (2 rho - 1)) / d,
// delta = (1-rho)^2 / (2 d), d = 4 - (1-rho)^2 (MBDyn's coefficients for equal steps). The first
// step, with no state two steps back, is a crank nicolson step.
#pragma once

#include <vector>

#include "testpeer_wire.h"

namespace dembridge::mbdyn::testpeer {

struct BodyState {
  V3 x{}, v{}, a{};                 // a = qp / m (what MBDyn sends with `accelerations, yes`)
  double theta = 0, theta_dot = 0, theta_ddot = 0;  // spin about global z
  V3 q{}, qp{};                     // momentum and its derivative (force)
  double q_theta = 0, qp_theta = 0;  // angular momentum about z and its derivative
};

struct OscillatorParameters {
  double mass = 1.0;
  double inertia = 1.0;
  V3 gravity{0, 0, 0};
  V3 force{0, 0, 0};               // constant absolute force on every node (MBDyn `force`)
  double derivatives_coefficient = 1e-6;  // MBDyn's default, multiplied by dt
  std::vector<BodyState> initial;  // one per node (x, v, theta, theta_dot)
  std::vector<double> tilt;        // per node: R = Rz(theta) * Rx(tilt), so all 3 axes vary
  std::vector<V3> offset;          // per node, node frame: MBDyn's `offset` of the point
  // A hinged body (MBDyn: revolute hinge to the ground + deformable hinge + body with its centre
  // of mass off the node): the node stays where it is and turns about spin_axis only, under the
  // peer's moment, a torsion spring -k (theta - theta0) - c theta_dot and the body's weight
  // (R c) x (m g) (c = cm_offset in the node frame, R the node's orientation).
  V3 spin_axis{0, 0, 1};           // global; the spin of every node is about this axis
  bool hinged = false;
  double torsion_stiffness = 0, torsion_damping = 0;
  V3 cm_offset{0, 0, 0};
  bool multistep = false;  // MBDyn `method: ms, rho` instead of crank nicolson
  double rho = 0.6;
};

// Loads from the peer on the nodes (global force, z moment about the node).
struct NodeLoads {
  std::vector<V3> force;
  std::vector<double> moment_z;
};

class OscillatorModel {
 public:
  explicit OscillatorModel(const OscillatorParameters& p);

  std::size_t size() const { return state_.size(); }
  const std::vector<BodyState>& state() const { return state_; }
  void accept(const std::vector<BodyState>& s) {
    older_ = state_;
    state_ = s;
  }
  // A resumed run: the converged state and the one a step before (empty before the first step).
  void restore(const std::vector<BodyState>& s, const std::vector<BodyState>& older) {
    state_ = s;
    older_ = older;
  }
  const std::vector<BodyState>& older() const { return older_; }

  // Norm of MBDyn's residual for state s under loads; without the momentum rows when
  // with_momentum is false (the initial-derivatives solve, where they are c F by construction).
  double residual_norm(const std::vector<BodyState>& s, const NodeLoads& loads, bool with_momentum = true) const;
  // One Newton update of the initial-derivatives solve on the current state (x, v kept).
  void derivatives_update(const NodeLoads& loads, double dt);
  // Crank-Nicolson predictor from the current (converged) state.
  std::vector<BodyState> predict(double dt) const;
  // The step from the current state solved for the given end-of-step loads.
  std::vector<BodyState> solve(double dt, const NodeLoads& loads) const;

  // Kinematics of node i's point (global frame) for the wire, at its offset (spec §4.3):
  // x = x_n + R o, v = v_n + w x R o, a = a_n + wdot x R o + w x (w x R o); R, w, wdot = node's.
  NodeState point_of(std::size_t i, const BodyState& b, std::uint32_t label) const;
  // Moment about the spin axis on the node from a load (f, m) at the point: m + (R o) x f, with
  // R o taken at the pose b the load was computed for (spec §4.3).
  double node_moment_z(std::size_t i, const BodyState& b, const V3& f, const V3& m) const;

 private:
  V3 total_force(std::size_t i, const NodeLoads& loads) const;
  // Moment about the spin axis of the spring, damper and weight of node i at (theta, theta_dot).
  double internal_moment(std::size_t i, double theta, double theta_dot) const;
  Mat3 orientation(std::size_t i, double theta) const;
  OscillatorParameters p_;
  std::vector<BodyState> state_;
  std::vector<double> theta0_;  // the torsion spring's rest angle: the initial one
  std::vector<BodyState> older_;  // the state one step before state_ (multistep); empty at first
  bool multistep_step() const { return p_.multistep && !older_.empty(); }
};

}  // namespace dembridge::mbdyn::testpeer
