#include "oscillator_model.h"

#include <cmath>

namespace dembridge::mbdyn::testpeer {

OscillatorModel::OscillatorModel(const OscillatorParameters& p) : p_(p), state_(p.initial) {
  p_.tilt.resize(state_.size(), 0.0);
  p_.offset.resize(state_.size(), V3{0, 0, 0});
  for (BodyState& b : state_) {
    for (int k = 0; k < 3; ++k) {
      b.q[k] = p_.mass * b.v[k];
      b.qp[k] = b.a[k] = 0;
    }
    b.q_theta = p_.inertia * b.theta_dot;
    b.qp_theta = b.theta_ddot = 0;
  }
}

V3 OscillatorModel::total_force(std::size_t i, const NodeLoads& loads) const {
  V3 f{};
  for (int k = 0; k < 3; ++k) f[k] = loads.force[i][k] + p_.mass * p_.gravity[k] + p_.force[k];
  return f;
}

namespace {
// Momentum row q - m v, with the round-off of v = q / m (a heavy node) taken as converged.
double momentum_row(double q, double mass, double v) {
  const double r = q - mass * v;
  return std::fabs(r) <= 1e-14 * std::fabs(q) ? 0.0 : r;
}
}  // namespace

double OscillatorModel::residual_norm(const std::vector<BodyState>& s, const NodeLoads& loads,
                                      bool with_momentum) const {
  double sum = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const V3 f = total_force(i, loads);
    for (int k = 0; k < 3; ++k) {
      const double rf = f[k] - s[i].qp[k];
      const double rq = with_momentum ? momentum_row(s[i].q[k], p_.mass, s[i].v[k]) : 0.0;
      sum += rf * rf + rq * rq;
    }
    const double rm = loads.moment_z[i] - s[i].qp_theta;
    const double rl = with_momentum ? momentum_row(s[i].q_theta, p_.inertia, s[i].theta_dot) : 0.0;
    sum += rm * rm + rl * rl;
  }
  return std::sqrt(sum);
}

void OscillatorModel::derivatives_update(const NodeLoads& loads, double dt) {
  const double c = p_.derivatives_coefficient * dt;
  for (std::size_t i = 0; i < state_.size(); ++i) {
    BodyState& b = state_[i];
    const V3 f = total_force(i, loads);
    for (int k = 0; k < 3; ++k) {
      b.qp[k] = f[k];
      b.q[k] = p_.mass * b.v[k] + c * f[k];
      b.a[k] = f[k] / p_.mass;
    }
    b.qp_theta = loads.moment_z[i];
    b.q_theta = p_.inertia * b.theta_dot + c * b.qp_theta;
    b.theta_ddot = b.qp_theta / p_.inertia;
  }
}

std::vector<BodyState> OscillatorModel::predict(double dt) const {
  std::vector<BodyState> out = state_;
  for (BodyState& b : out) {
    for (int k = 0; k < 3; ++k) {
      b.x[k] += dt * b.v[k];
      b.q[k] += dt * b.qp[k];
    }
    b.theta += dt * b.theta_dot;
    b.q_theta += dt * b.qp_theta;
  }
  return out;
}

std::vector<BodyState> OscillatorModel::solve(double dt, const NodeLoads& loads) const {
  const double h = dt / 2;
  std::vector<BodyState> out = state_;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const BodyState& o = state_[i];
    BodyState& n = out[i];
    const V3 f = total_force(i, loads);
    for (int k = 0; k < 3; ++k) {
      n.qp[k] = f[k];
      n.q[k] = o.q[k] + h * (o.qp[k] + f[k]);
      n.v[k] = n.q[k] / p_.mass;
      n.x[k] = o.x[k] + h * (o.v[k] + n.v[k]);
      n.a[k] = f[k] / p_.mass;
    }
    n.qp_theta = loads.moment_z[i];
    n.q_theta = o.q_theta + h * (o.qp_theta + n.qp_theta);
    n.theta_dot = n.q_theta / p_.inertia;
    n.theta = o.theta + h * (o.theta_dot + n.theta_dot);
    n.theta_ddot = n.qp_theta / p_.inertia;
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
