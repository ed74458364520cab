// 3-vectors for the mesh geometry. Every helper spells out its operation order, because the
// LIGGGHTS 3.8 results are reproduced bit for bit (spec liggghts-walls §4, §7).
#pragma once

#include <array>
#include <cmath>

namespace dembridge::mesh {

using Vec3 = std::array<double, 3>;

inline Vec3 add(const Vec3 &a, const Vec3 &b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 sub(const Vec3 &a, const Vec3 &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 scale(const Vec3 &a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec3 &a, const Vec3 &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3 &a, const Vec3 &b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3 &a) { return std::sqrt(dot(a, a)); }
// a * (1/s): LIGGGHTS divides vectors by multiplying with the reciprocal.
inline Vec3 div_by(const Vec3 &a, double s)
{
  const double inv = 1.0 / s;
  return {inv * a[0], inv * a[1], inv * a[2]};
}
inline bool all_finite(const Vec3 &a) { return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]); }

// Quaternions (w, x, y, z) and the rotation q (0,v) q^-1 as two Hamilton products.
using Quat = std::array<double, 4>;
inline Quat quat_mul(const Quat &a, const Quat &b)
{
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + b[0] * a[1] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] + b[0] * a[2] + a[3] * b[1] - a[1] * b[3],
          a[0] * b[3] + b[0] * a[3] + a[1] * b[2] - a[2] * b[1]};
}
inline Vec3 quat_rotate(const Vec3 &v, const Quat &q)
{
  const Quat t = quat_mul(q, {0.0, v[0], v[1], v[2]});
  const Quat r = quat_mul(t, {q[0], -q[1], -q[2], -q[3]});
  return {r[1], r[2], r[3]};
}
// Rotation by angle phi about the unit axis a.
inline Quat axis_angle_quat(const Vec3 &a, double phi)
{
  const double s = std::sin(phi * 0.5);
  return {std::cos(phi * 0.5), a[0] * s, a[1] * s, a[2] * s};
}

}  // namespace dembridge::mesh
