// Rotation matrix (body -> space) of a LAMMPS quaternion (w, x, y, z), as the spring loops form it: one
// matrix per atom and step can serve every spring whose points or plane that atom carries.
#pragma once

#include "spring_vec3.h"

namespace dembridge::springs {

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

}  // namespace dembridge::springs
