#include "rigid_replay.h"

#include <cmath>

#include "axis_inertia.h"

namespace replay {

namespace dt = dembridge::torsion;

// Rotation-vector exponential I + a[θ]x + b[θ]x² (spec §1.2), Parmec's Taylor series below |θ|² < 0.0305;
// q3 reproduces the (3,1)/(1,3) typo θ2θ3 instead of θ1θ3.
Mat3 expmap(const V3& th, bool q3) {
  const double o1 = th(0), o2 = th(1), o3 = th(2);
  const double v0 = o1 * o1, v1 = o2 * o2, v2 = o3 * o3, a = v0 + v1 + v2;
  double sx, cx;
  if (a < 3.0461741978671E-02) {
    sx = 1.0 + (-1.666666666666667E-1 + (8.333333333333333E-3 + (-1.984126984126984E-4 + (2.755731922398589E-6 +
         (-2.505210838544172E-8 + 1.605904383682161E-10 * a) * a) * a) * a) * a) * a;
    cx = 0.5 + (-4.166666666666667E-2 + (1.388888888888889E-3 + (-2.480158730158730E-5 + (2.755731922398589E-7 +
         (-2.087675698786810E-9 + 1.147074559772972E-11 * a) * a) * a) * a) * a) * a;
  } else {
    const double r = std::sqrt(a);
    sx = std::sin(r) / r;
    cx = (1.0 - std::cos(r)) / a;
  }
  const double v01 = o1 * o2, v02 = q3 ? o2 * o3 : o1 * o3, v12 = o2 * o3;
  const double s0 = sx * o1, s1 = sx * o2, s2 = sx * o3;
  Mat3 L;
  L << 1.0 - cx * (v2 + v1), cx * v01 - s2, cx * v02 + s1,  //
      cx * v01 + s2, 1.0 - cx * (v2 + v0), cx * v12 - s0,   //
      cx * v02 - s1, cx * v12 + s0, 1.0 - cx * (v1 + v0);
  return L;
}

dt::Mat3 to_rowmajor(const Mat3& m) {
  return {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)};
}

// Unforced half rotation Λ_{1/2} = Λ_0 exp(h/2 Ω_0); Q1: stored spatial ω = Λ_{1/2} (h/2 Ω_0).
RigidReplay::RigidReplay(std::vector<Body> bodies, std::vector<Torsion> springs, double h, bool q1, bool q3)
    : bodies_(std::move(bodies)), springs_(std::move(springs)), h_(h), q3_(q3) {
  for (auto& b : bodies_) {
    b.L = b.L * expmap(0.5 * h_ * b.W, q3_);
    b.w = q1 ? V3(b.L * (0.5 * h_ * b.W)) : V3(b.L * b.W);
  }
}

void RigidReplay::step() {
  for (auto& b : bodies_) b.t = V3::Zero();
  for (auto& s : springs_) {
    Body& b1 = bodies_[s.part1];
    dt::TorsionStepInput in;
    in.frame = dt::current_frame(s.reference, to_rowmajor(b1.L));
    V3 rel = b1.w;
    if (s.part2 >= 0) rel -= bodies_[s.part2].w;
    in.relative_omega = {rel(0), rel(1), rel(2)};
    in.dt = h_;
    if (s.law.needs_axis_inertia()) {
      const dt::Mat3 w1 = dt::spatial_inverse_inertia(to_rowmajor(b1.L), to_rowmajor(b1.J.inverse()));
      dt::Mat3 w2;
      if (s.part2 >= 0) {
        const Body& b2 = bodies_[s.part2];
        w2 = dt::spatial_inverse_inertia(to_rowmajor(b2.L), to_rowmajor(b2.J.inverse()));
      }
      in.axis_inertia = dt::axis_inertias(in.frame, w1, s.part2 >= 0 ? &w2 : nullptr);
      if (parmec_inertia_) {
        const dt::Mat3 j2 = s.part2 >= 0 ? to_rowmajor(bodies_[s.part2].J.inverse()) : dt::Mat3{};
        in.axis_inertia = dt::axis_inertias_parmec(in.frame, to_rowmajor(b1.J.inverse()), s.part2 >= 0 ? &j2 : nullptr);
      }
    }
    s.last = dt::advance_torsion(s.law, s.state, in);
    const V3 t(s.last.on_part1[0], s.last.on_part1[1], s.last.on_part1[2]);
    b1.t += t;
    if (s.part2 >= 0) bodies_[s.part2].t -= t;
  }
  for (auto& b : bodies_) {
    const V3 T = b.L.transpose() * b.t;
    const Mat3 Ji = b.J.inverse();
    const V3 Wh = Ji * (expmap(-0.5 * h_ * b.W, q3_) * (b.J * b.W) + 0.5 * h_ * T);
    b.W = b.W + Ji * (h_ * (T - Wh.cross(b.J * Wh)));
    b.L = b.L * expmap(h_ * b.W, q3_);
    b.w = b.L * b.W;
  }
}

}  // namespace replay
