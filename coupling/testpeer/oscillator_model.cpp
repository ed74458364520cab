#include "oscillator_model.h"

#include <cmath>

namespace dembridge::mbdyn::testpeer {

namespace {
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
// Rotation by angle about the unit axis a (Rodrigues).
Mat3 rotation_about(const V3& a, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  return {{{c + t * a[0] * a[0], t * a[0] * a[1] - s * a[2], t * a[0] * a[2] + s * a[1]},
           {t * a[0] * a[1] + s * a[2], c + t * a[1] * a[1], t * a[1] * a[2] - s * a[0]},
           {t * a[0] * a[2] - s * a[1], t * a[1] * a[2] + s * a[0], c + t * a[2] * a[2]}}};
}
}  // namespace

OscillatorModel::OscillatorModel(const OscillatorParameters& p) : p_(p), state_(p.initial) {
  const double n = std::sqrt(dot(p_.spin_axis, p_.spin_axis));
  for (double& c : p_.spin_axis) c /= n;
  for (const BodyState& b : state_) theta0_.push_back(b.theta);
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

Mat3 OscillatorModel::orientation(std::size_t i, double theta) const {
  return multiply(rotation_about(p_.spin_axis, theta), rotation_about_x(p_.tilt[i]));
}

double OscillatorModel::internal_moment(std::size_t i, double theta, double theta_dot) const {
  if (!p_.hinged) return 0.0;
  V3 weight;
  for (int k = 0; k < 3; ++k) weight[k] = p_.mass * p_.gravity[k];
  const V3 arm = rotate_vector(orientation(i, theta), p_.cm_offset);
  return -p_.torsion_stiffness * (theta - theta0_[i]) - p_.torsion_damping * theta_dot +
         dot(cross(arm, weight), p_.spin_axis);
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
    for (int k = 0; k < 3 && !p_.hinged; ++k) {
      const double rf = f[k] - s[i].qp[k];
      const double rq = with_momentum ? momentum_row(s[i].q[k], p_.mass, s[i].v[k]) : 0.0;
      sum += rf * rf + rq * rq;
    }
    const double rm = loads.moment_z[i] + internal_moment(i, s[i].theta, s[i].theta_dot) - s[i].qp_theta;
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
    for (int k = 0; k < 3 && !p_.hinged; ++k) {
      b.qp[k] = f[k];
      b.q[k] = p_.mass * b.v[k] + c * f[k];
      b.a[k] = f[k] / p_.mass;
    }
    b.qp_theta = loads.moment_z[i] + internal_moment(i, b.theta, b.theta_dot);
    b.q_theta = p_.inertia * b.theta_dot + c * b.qp_theta;
    b.theta_ddot = b.qp_theta / p_.inertia;
  }
}

namespace {
// MBDyn's two-step coefficients at a constant step (oscillator_model.h).
struct Multistep {
  double a1, a2, b0, b1, b2;
  Multistep(double rho, double dt) {
    const double r2 = (1 - rho) * (1 - rho), d = 4 - r2;
    const double beta = (3 * r2 + 4 * (2 * rho - 1)) / d, delta = 0.5 * r2 / d;
    a1 = 1 - beta;
    a2 = beta;
    b0 = dt * (delta + 0.5);
    b1 = dt * (0.5 * beta + 0.5 - 2 * delta);
    b2 = dt * (0.5 * beta + delta);
  }
  double state(double y1, double y2, double yp, double yp1, double yp2) const {
    return a1 * y1 + a2 * y2 + b0 * yp + b1 * yp1 + b2 * yp2;
  }
  static double derivative(double dt, double y1, double y2, double yp1, double yp2) {
    return (-12 * y1 + 12 * y2) / dt + 8 * yp1 + 5 * yp2;
  }
};
}  // namespace

std::vector<BodyState> OscillatorModel::predict(double dt) const {
  std::vector<BodyState> out = state_;
  if (multistep_step()) {
    const Multistep ms(p_.rho, dt);
    for (std::size_t i = 0; i < out.size(); ++i) {
      const BodyState &o = state_[i], &oo = older_[i];
      BodyState& b = out[i];
      auto pair = [&](double& y, double& yp, double y1, double y2, double yp1, double yp2) {
        yp = Multistep::derivative(dt, y1, y2, yp1, yp2);
        y = ms.state(y1, y2, yp, yp1, yp2);
      };
      for (int k = 0; k < 3; ++k) {
        pair(b.x[k], b.v[k], o.x[k], oo.x[k], o.v[k], oo.v[k]);
        pair(b.q[k], b.qp[k], o.q[k], oo.q[k], o.qp[k], oo.qp[k]);
      }
      pair(b.theta, b.theta_dot, o.theta, oo.theta, o.theta_dot, oo.theta_dot);
      pair(b.q_theta, b.qp_theta, o.q_theta, oo.q_theta, o.qp_theta, oo.qp_theta);
    }
    return out;
  }
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
  if (multistep_step()) {
    // The loads have no Jacobian and there is no internal moment (no hinge): explicit in F.
    const Multistep ms(p_.rho, dt);
    for (std::size_t i = 0; i < out.size(); ++i) {
      const BodyState &o = state_[i], &oo = older_[i];
      BodyState& n = out[i];
      const V3 f = total_force(i, loads);
      for (int k = 0; k < 3; ++k) {
        n.qp[k] = f[k];
        n.q[k] = ms.state(o.q[k], oo.q[k], f[k], o.qp[k], oo.qp[k]);
        n.v[k] = n.q[k] / p_.mass;
        n.x[k] = ms.state(o.x[k], oo.x[k], n.v[k], o.v[k], oo.v[k]);
        n.a[k] = f[k] / p_.mass;
      }
      n.qp_theta = loads.moment_z[i];
      n.q_theta = ms.state(o.q_theta, oo.q_theta, n.qp_theta, o.qp_theta, oo.qp_theta);
      n.theta_dot = n.q_theta / p_.inertia;
      n.theta = ms.state(o.theta, oo.theta, n.theta_dot, o.theta_dot, oo.theta_dot);
      n.theta_ddot = n.qp_theta / p_.inertia;
    }
    return out;
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    const BodyState& o = state_[i];
    BodyState& n = out[i];
    const V3 f = total_force(i, loads);
    for (int k = 0; k < 3 && !p_.hinged; ++k) {
      n.qp[k] = f[k];
      n.q[k] = o.q[k] + h * (o.qp[k] + f[k]);
      n.v[k] = n.q[k] / p_.mass;
      n.x[k] = o.x[k] + h * (o.v[k] + n.v[k]);
      n.a[k] = f[k] / p_.mass;
    }
    // J w = q_{-1} + h (qp_{-1} + M + M_int(theta(w), w)), theta(w) = theta_{-1} + h (w_{-1} + w):
    // Newton on w (one iteration when there is no internal moment)
    double w = o.theta_dot;
    for (int it = 0; it < 50; ++it) {
      auto g = [&](double ww) {
        const double th = o.theta + h * (o.theta_dot + ww);
        return p_.inertia * ww - o.q_theta - h * (o.qp_theta + loads.moment_z[i] + internal_moment(i, th, ww));
      };
      const double e = 1e-7 * (1 + std::fabs(w)), g0 = g(w);
      const double step = g0 / ((g(w + e) - g0) / e);
      w -= step;
      if (std::fabs(step) <= 1e-15 * (1 + std::fabs(w))) break;
    }
    n.theta = o.theta + h * (o.theta_dot + w);
    n.qp_theta = loads.moment_z[i] + internal_moment(i, n.theta, w);
    n.q_theta = o.q_theta + h * (o.qp_theta + n.qp_theta);
    n.theta_dot = n.q_theta / p_.inertia;
    n.theta_ddot = n.qp_theta / p_.inertia;
  }
  return out;
}

NodeState OscillatorModel::point_of(std::size_t i, const BodyState& b, std::uint32_t label) const {
  NodeState n;
  n.label = label;
  n.R = orientation(i, b.theta);
  for (int k = 0; k < 3; ++k) {
    n.w[k] = b.theta_dot * p_.spin_axis[k];
    n.wdot[k] = b.theta_ddot * p_.spin_axis[k];
  }
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
  const V3 t = cross(rotate_vector(orientation(i, b.theta), p_.offset[i]), f);
  return dot(m, p_.spin_axis) + dot(t, p_.spin_axis);
}

}  // namespace dembridge::mbdyn::testpeer
