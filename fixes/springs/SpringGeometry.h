// Spring direction modes and per-step kinematics (spec parmec-springs §2).
#pragma once

#include "Vec3.h"

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
// Inline (below), as relative_velocity: evaluated for every spring every step.
SpringFrame spring_frame(DirectionMode mode, const Vec3& d, const SpringKinematics& kin);

// stroke0 from the reference points (spec §2.1 table); 0 for Plane.
double reference_stroke0(DirectionMode mode, const Vec3& d, const Vec3& P1, const Vec3& P2);

// Plane mode stores the projection of point1 onto the reference plane as part2's material point (spec §2.1).
Vec3 plane_anchor(const Vec3& P1, const Vec3& plane_point, const Vec3& unit_normal);

// u = (v_k + w_k x b) - (v_j + w_j x a); pass has_part2 = false for a spatial anchor.
Vec3 relative_velocity(const Vec3& v1, const Vec3& w1, const Vec3& a, bool has_part2, const Vec3& v2, const Vec3& w2,
                       const Vec3& b);

inline Vec3 project_out(const Vec3& w, const Vec3& d) { return w - dot(w, d) * d; }

inline SpringFrame spring_frame(DirectionMode mode, const Vec3& d, const SpringKinematics& kin) {
  SpringFrame f;
  const Vec3 w = kin.q - kin.p;
  f.distance = norm(w);
  switch (mode) {
    case DirectionMode::Follower:
      f.len = f.distance;
      if (f.len > 0.0) f.z = {w[0] / f.len, w[1] / f.len, w[2] / f.len};
      break;
    case DirectionMode::Constant:
      f.len = dot(w, d);
      f.z = d;  // fixed in space, not co-rotated even with part2 >= 0 (spec §2.1)
      break;
    case DirectionMode::Planar: {
      const Vec3 wp = project_out(w, d);
      f.len = norm(wp);
      if (f.len > 0.0) f.z = {wp[0] / f.len, wp[1] / f.len, wp[2] / f.len};
      break;
    }
    case DirectionMode::Plane:
      f.z = kin.normal;
      f.len = dot(kin.p - kin.q, kin.normal);  // signed distance of point1 from the plane
      break;
  }
  f.velocity = dot(f.z, kin.u);
  f.u_tangential = kin.u - f.velocity * f.z;
  return f;
}

inline Vec3 relative_velocity(const Vec3& v1, const Vec3& w1, const Vec3& a, bool has_part2, const Vec3& v2,
                              const Vec3& w2, const Vec3& b) {
  const Vec3 u1 = v1 + cross(w1, a);
  if (!has_part2) return Vec3{} - u1;
  return (v2 + cross(w2, b)) - u1;
}

// Unit vector or throws std::invalid_argument("<what>: ... must be non-zero").
Vec3 unit_direction(const Vec3& d, const char* what);

}  // namespace dembridge::springs
