// Spring direction modes and per-step kinematics (spec parmec-springs §2).
#pragma once

#include "spring_vec3.h"

namespace dembridge::springs {

enum class DirectionMode {
  Follower,  // z = (q - p)/|q - p|
  Constant,  // z = d fixed in space, len = (q - p).d
  Planar,    // (q - p) projected on the plane normal to d
  Plane      // point-to-plane: z = current plane normal n, len = (p - q).n
};

// Current attachment points and motion of one spring at the force evaluation.
struct SpringKinematics {
  Vec3 p{};       // point1 on part1
  Vec3 q{};       // point2 on part2 (or the fixed anchor); PLANE: the plane's material anchor point
  Vec3 u{};       // velocity of point2 relative to point1 (spec §2.2)
  Vec3 normal{};  // PLANE only: current unit plane normal (Λ_k n_ref, or n_ref for part2 = -1)
};

// What the force law needs from the geometry.
struct SpringFrame {
  double len = 0.0;       // length measure of the mode; stroke = len - stroke0
  Vec3 z{};               // unit force direction (0 if undefined: zero-length follower/planar)
  double velocity = 0.0;  // z.u (dashpot argument)
  Vec3 u_tangential{};    // u - velocity z (friction)
  double distance = 0.0;  // |q - p|, HISTORY 'LENGTH' in every mode
};

// d: the unit direction for Constant/Planar; ignored by Follower and Plane (which uses kin.normal).
// parmec: Parmec's rounding (forces.ispc as its build compiles it): the unit direction as (1/len)·w instead
// of w/len, and dot products and projections by fused multiply-adds (spring_vec3.h).
// Inline (below), as relative_velocity: evaluated for every spring every step.
[[gnu::always_inline]] inline SpringFrame spring_frame(DirectionMode mode, const Vec3& d, const SpringKinematics& kin,
                                                       bool parmec = false);

// stroke0 from the reference points (spec §2.1 table); 0 for Plane.
double reference_stroke0(DirectionMode mode, const Vec3& d, const Vec3& P1, const Vec3& P2);

// Plane mode stores the projection of point1 onto the reference plane as part2's material point (spec §2.1).
Vec3 plane_anchor(const Vec3& P1, const Vec3& plane_point, const Vec3& unit_normal);

// u = (v_k + w_k x b) - (v_j + w_j x a); pass has_part2 = false for a spatial anchor.
Vec3 relative_velocity(const Vec3& v1, const Vec3& w1, const Vec3& a, bool has_part2, const Vec3& v2, const Vec3& w2,
                       const Vec3& b);
// The same velocity rounded as Parmec forms it: u = −v_j, u −= w_j × a, u += v_k, u += w_k × b (fused
// cross products).
Vec3 relative_velocity_parmec(const Vec3& v1, const Vec3& w1, const Vec3& a, bool has_part2, const Vec3& v2,
                              const Vec3& w2, const Vec3& b);

inline Vec3 project_out(const Vec3& w, const Vec3& d) { return w - dot(w, d) * d; }

inline Vec3 unit_of(const Vec3& w, double len, bool reciprocal) {
  if (!(len > 0.0)) return {0.0, 0.0, 0.0};
  if (!reciprocal) return {w[0] / len, w[1] / len, w[2] / len};
  const double inv = 1.0 / len;
  return {inv * w[0], inv * w[1], inv * w[2]};
}

[[gnu::always_inline]] inline SpringFrame spring_frame(DirectionMode mode, const Vec3& d, const SpringKinematics& kin,
                                                       bool parmec) {
  SpringFrame f;
  auto dotp = [parmec](const Vec3& a, const Vec3& b) { return parmec ? dot_fused(a, b) : dot(a, b); };
  // w - (w.d) d (Parmec: w -= s d, one rounding per component)
  auto minus = [parmec](const Vec3& w, double s, const Vec3& d) {
    return parmec ? Vec3{std::fma(-s, d[0], w[0]), std::fma(-s, d[1], w[1]), std::fma(-s, d[2], w[2])} : w - s * d;
  };
  const Vec3 w = kin.q - kin.p;
  // HISTORY 'LENGTH' is Parmec's C++ output code (not contracted: one rounding per operation, also with parmec)
  f.distance = std::sqrt(dot(w, w));
  switch (mode) {
    case DirectionMode::Follower:
      f.len = parmec ? std::sqrt(dot_fused(w, w)) : f.distance;
      f.z = unit_of(w, f.len, parmec);
      break;
    case DirectionMode::Constant:
      f.len = dotp(w, d);
      f.z = d;  // fixed in space, not co-rotated even with part2 >= 0 (spec §2.1)
      break;
    case DirectionMode::Planar: {
      const Vec3 wp = minus(w, dotp(w, d), d);
      f.len = std::sqrt(dotp(wp, wp));
      f.z = unit_of(wp, f.len, parmec);
      break;
    }
    case DirectionMode::Plane:
      f.z = kin.normal;
      f.len = dotp(kin.p - kin.q, kin.normal);  // signed distance of point1 from the plane
      break;
  }
  f.velocity = dotp(f.z, kin.u);
  f.u_tangential = minus(kin.u, f.velocity, f.z);
  return f;
}

inline Vec3 relative_velocity(const Vec3& v1, const Vec3& w1, const Vec3& a, bool has_part2, const Vec3& v2,
                              const Vec3& w2, const Vec3& b) {
  const Vec3 u1 = v1 + cross(w1, a);
  if (!has_part2) return Vec3{} - u1;
  return (v2 + cross(w2, b)) - u1;
}

inline Vec3 relative_velocity_parmec(const Vec3& v1, const Vec3& w1, const Vec3& a, bool has_part2, const Vec3& v2,
                                     const Vec3& w2, const Vec3& b) {
  Vec3 u = Vec3{-v1[0], -v1[1], -v1[2]} - cross_fused(w1, a);
  if (has_part2) u = (u + v2) + cross_fused(w2, b);
  return u;
}

// Unit vector or throws std::invalid_argument("<what>: ... must be non-zero").
Vec3 unit_direction(const Vec3& d, const char* what);

}  // namespace dembridge::springs
