// Quaternions (w, x, y, z, LAMMPS's order) of the math layer: the Hamilton product, the rotation of a
// vector, the rotation about an axis, and the body -> space rotation matrix of a unit quaternion.
// Operation orders as the mesh movers (LIGGGHTS 3.8) and the Parmec spring loops need them, bit for bit.
#pragma once

#include "math/vec3.h"

namespace dembridge::math {

using Quat = std::array<double, 4>;

inline Quat quat_mul(const Quat &a, const Quat &b)
{
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + b[0] * a[1] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] + b[0] * a[2] + a[3] * b[1] - a[1] * b[3],
          a[0] * b[3] + b[0] * a[3] + a[1] * b[2] - a[2] * b[1]};
}
// q (0,v) q^-1 as two Hamilton products (LIGGGHTS's mesh rotation).
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

// Rotation matrix (body -> space) of a LAMMPS quaternion, as the Parmec spring, torsion and rigid fixes form
// it: one matrix per atom and step can serve every spring whose points or plane that atom carries.
struct BodyRotation {
  double m[3][3];
  static BodyRotation identity() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }
  static BodyRotation of(const double *q)
  {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    BodyRotation r;
    r.m[0][0] = w * w + x * x - y * y - z * z;
    r.m[0][1] = 2.0 * (x * y - w * z);
    r.m[0][2] = 2.0 * (x * z + w * y);
    r.m[1][0] = 2.0 * (x * y + w * z);
    r.m[1][1] = w * w - x * x + y * y - z * z;
    r.m[1][2] = 2.0 * (y * z - w * x);
    r.m[2][0] = 2.0 * (x * z - w * y);
    r.m[2][1] = 2.0 * (y * z + w * x);
    r.m[2][2] = w * w - x * x - y * y + z * z;
    return r;
  }
  Vec3 apply(const Vec3 &v) const
  {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
  }
  Vec3 apply_t(const Vec3 &v) const
  {
    return {m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2], m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
            m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2]};
  }
};

}  // namespace dembridge::math
