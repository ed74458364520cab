#include "oscillator_model.h"

namespace dembridge::mbdyn::testpeer {

OscillatorModel::OscillatorModel(const OscillatorParameters& p) : p_(p), state_(p.initial) {
  p_.tilt.resize(state_.size(), 0.0);
}

void OscillatorModel::set_loads_at_current_state(const std::vector<V3>& force, const std::vector<double>& mz) {
  for (std::size_t i = 0; i < state_.size(); ++i) {
    for (int k = 0; k < 3; ++k) state_[i].a[k] = force[i][k] / p_.mass + p_.gravity[k];
    state_[i].theta_ddot = mz[i] / p_.inertia;
  }
}

std::vector<BodyState> OscillatorModel::predict(double dt, bool first_step) const {
  if (first_step) return state_;
  std::vector<BodyState> out = state_;
  for (BodyState& b : out) {
    for (int k = 0; k < 3; ++k) {
      b.x[k] += dt * b.v[k] + 0.5 * dt * dt * b.a[k];
      b.v[k] += dt * b.a[k];
    }
    b.theta += dt * b.theta_dot + 0.5 * dt * dt * b.theta_ddot;
    b.theta_dot += dt * b.theta_ddot;
  }
  return out;
}

std::vector<BodyState> OscillatorModel::step(double dt, const std::vector<V3>& force,
                                             const std::vector<double>& mz) const {
  std::vector<BodyState> out = state_;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const BodyState& o = state_[i];
    BodyState& n = out[i];
    for (int k = 0; k < 3; ++k) {
      n.a[k] = force[i][k] / p_.mass + p_.gravity[k];
      n.v[k] = o.v[k] + 0.5 * dt * (o.a[k] + n.a[k]);
      n.x[k] = o.x[k] + 0.5 * dt * (o.v[k] + n.v[k]);
    }
    n.theta_ddot = mz[i] / p_.inertia;
    n.theta_dot = o.theta_dot + 0.5 * dt * (o.theta_ddot + n.theta_ddot);
    n.theta = o.theta + 0.5 * dt * (o.theta_dot + n.theta_dot);
  }
  return out;
}

NodeState OscillatorModel::node_of(std::size_t i, const BodyState& b, std::uint32_t label) const {
  NodeState n;
  n.label = label;
  n.x = b.x;
  n.v = b.v;
  n.a = b.a;
  n.R = multiply(rotation_about_z(b.theta), rotation_about_x(p_.tilt[i]));
  n.w = {0, 0, b.theta_dot};
  n.wdot = {0, 0, b.theta_ddot};
  return n;
}

}  // namespace dembridge::mbdyn::testpeer
