#include "oscillator_model.h"

namespace dembridge::mbdyn::testpeer {

OscillatorModel::OscillatorModel(const OscillatorParameters& p) : p_(p), state_(p.initial) {
  p_.tilt.resize(state_.size(), 0.0);
  p_.offset.resize(state_.size(), V3{0, 0, 0});
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

namespace {
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
}  // namespace

NodeState OscillatorModel::point_of(std::size_t i, const BodyState& b, std::uint32_t label) const {
  NodeState n;
  n.label = label;
  n.R = multiply(rotation_about_z(b.theta), rotation_about_x(p_.tilt[i]));
  n.w = {0, 0, b.theta_dot};
  n.wdot = {0, 0, b.theta_ddot};
  const V3 arm = rotate_vector(n.R, p_.offset[i]);
  const V3 w_arm = cross(n.w, arm);
  const V3 wdot_arm = cross(n.wdot, arm);
  const V3 w_w_arm = cross(n.w, w_arm);
  for (int k = 0; k < 3; ++k) {
    n.x[k] = b.x[k] + arm[k];
    n.v[k] = b.v[k] + w_arm[k];
    n.a[k] = b.a[k] + wdot_arm[k] + w_w_arm[k];
  }
  return n;
}

double OscillatorModel::node_moment_z(std::size_t i, const BodyState& b, const V3& f, const V3& m) const {
  const Mat3 R = multiply(rotation_about_z(b.theta), rotation_about_x(p_.tilt[i]));
  return m[2] + cross(rotate_vector(R, p_.offset[i]), f)[2];
}

}  // namespace dembridge::mbdyn::testpeer
