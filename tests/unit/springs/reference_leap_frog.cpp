#include "reference_leap_frog.h"

#include <cmath>

namespace reference {

namespace ds = dembridge::springs;

Vec3 to_vec(const V3& v) { return {v(0), v(1), v(2)}; }
V3 to_v3(const Vec3& v) { return V3(v[0], v[1], v[2]); }

ds::BodyMass Body::mass_properties() const {
  ds::BodyMass b;
  b.mass = mass;
  const Mat3 Ji = J.inverse();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b.inv_inertia[3 * i + j] = Ji(i, j);
  b.centre = to_vec(X);
  return b;
}

// Rotation-vector exponential I + a[θ]x + b[θ]x^2, Taylor series for small angles (spec §1.2).
// q3 reproduces Parmec's typo: the (3,1)/(1,3) entries of θθ^T use θ2θ3 instead of θ1θ3.
Mat3 expmap(const V3& th, bool q3) {
  const double t2 = th.squaredNorm();
  double a, b;
  if (t2 < 0.0305) {
    a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0)));
    b = 0.5 * (1.0 - t2 / 12.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0 * (1.0 - t2 / 90.0))));
  } else {
    const double t = std::sqrt(t2);
    a = std::sin(t) / t;
    b = (1.0 - std::cos(t)) / t2;
  }
  Mat3 S;
  S << 0.0, -th(2), th(1), th(2), 0.0, -th(0), -th(1), th(0), 0.0;
  Mat3 TT = th * th.transpose();
  if (q3) TT(2, 0) = TT(0, 2) = th(1) * th(2);
  return Mat3::Identity() + a * S + b * (TT - t2 * Mat3::Identity());
}

Spring LeapFrog::make_spring(int part1, const V3& P1, int part2, const V3& P2, ds::DirectionMode mode, const Vec3& d,
                             const ds::SpringLaw& law) {
  Spring s;
  s.part1 = part1;
  s.part2 = part2;
  s.P1 = P1;
  s.mode = mode;
  s.law = law;
  s.state = ds::SpringState::initial(law);
  if (mode == ds::DirectionMode::Plane) {
    s.d = ds::unit_direction(d, "plane normal");
    s.P2 = to_v3(ds::plane_anchor(to_vec(P1), to_vec(P2), s.d));
  } else {
    s.d = mode == ds::DirectionMode::Follower ? Vec3{} : ds::unit_direction(d, "direction");
    s.P2 = P2;
  }
  s.stroke0 = ds::reference_stroke0(mode, s.d, to_vec(s.P1), to_vec(s.P2));
  return s;
}

LeapFrog::LeapFrog(std::vector<Body> bodies, std::vector<Spring> springs, Options opt)
    : bodies_(std::move(bodies)), springs_(std::move(springs)), opt_(opt) {
  start();
}

// Unforced half drift x_{1/2} = x_0 + h/2 v_0, Λ_{1/2} = Λ_0 exp(h/2 Ω_0) (spec §1.1); Q1: the stored
// spatial ω is Λ_{1/2} (h/2 Ω_0). Velocities are then restrained once (after the drift: Q20).
void LeapFrog::start() {
  const double hh = 0.5 * opt_.h;
  for (auto& b : bodies_) {
    b.x = b.x + hh * b.v;
    b.L = b.L * expmap(hh * b.W, opt_.q3);
    b.w = opt_.q1 ? V3(b.L * (hh * b.W)) : V3(b.L * b.W);
    for (const auto& e : b.restrain_linear) b.v -= e.dot(b.v) * e;
    for (const auto& e : b.restrain_angular) b.w -= e.dot(b.w) * e;
    if (!b.restrain_angular.empty()) b.W = b.L.transpose() * b.w;
  }
}

void LeapFrog::step() {
  for (auto& b : bodies_) {
    b.f = b.mass * opt_.gravity;
    b.t = V3::Zero();
  }
  for (auto& s : springs_) {
    Body& bj = bodies_[s.part1];
    const V3 p = bj.x + bj.L * (s.P1 - bj.X);
    const V3 a = p - bj.x;
    V3 q = s.P2, b = V3::Zero();
    ds::SpringKinematics kin;
    Vec3 u;
    if (s.part2 >= 0) {
      const Body& bk = bodies_[s.part2];
      q = bk.x + bk.L * (s.P2 - bk.X);
      b = q - bk.x;
      u = ds::relative_velocity(to_vec(bj.v), to_vec(bj.w), to_vec(a), true, to_vec(bk.v), to_vec(bk.w), to_vec(b));
      kin.normal = to_vec(bk.L * to_v3(s.d));
    } else {
      u = ds::relative_velocity(to_vec(bj.v), to_vec(bj.w), to_vec(a), false, {}, {}, {});
      kin.normal = s.d;
    }
    kin.p = to_vec(p);
    kin.q = to_vec(q);
    kin.u = u;
    const ds::SpringFrame fr = ds::spring_frame(s.mode, s.d, kin);
    ds::SpringStepInput in;
    in.stroke0 = s.stroke0;
    in.time = time_;
    in.dt = opt_.h;
    if (s.law.needs_equivalent_mass()) {
      const ds::BodyMass mj = bj.mass_properties();
      ds::BodyMass mk;
      if (s.part2 >= 0) mk = bodies_[s.part2].mass_properties();
      in.equivalent_mass = ds::equivalent_mass(mj, to_vec(s.P1), s.part2 >= 0 ? &mk : nullptr, to_vec(s.P2), fr.z,
                                               opt_.eqm_arm);
    }
    s.last = ds::advance_spring(s.law, s.state, fr, in);
    const V3 frc = to_v3(s.last.on_part1);
    bj.f += frc;
    bj.t += a.cross(frc);
    if (s.part2 >= 0) {
      Body& bk = bodies_[s.part2];
      bk.f -= frc;
      bk.t -= b.cross(frc);
    }
  }
  const double h = opt_.h;
  for (auto& b : bodies_) {
    for (const auto& e : b.restrain_linear) b.f -= e.dot(b.f) * e;
    for (const auto& e : b.restrain_angular) b.t -= e.dot(b.t) * e;
    // body-frame rotational update (spec §1.2)
    const V3 T = b.L.transpose() * b.t;
    const Mat3 Ji = b.J.inverse();
    const V3 Wh = Ji * (expmap(-0.5 * h * b.W, opt_.q3) * (b.J * b.W) + 0.5 * h * T);
    b.W = b.W + h * Ji * (T - Wh.cross(b.J * Wh));
    b.v = b.v + (h / b.mass) * b.f;
    b.L = b.L * expmap(h * b.W, opt_.q3);
    b.w = b.L * b.W;
    b.x = b.x + h * b.v;
  }
  time_ += h;
  ++steps_;
}

}  // namespace reference
