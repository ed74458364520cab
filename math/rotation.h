// Row-major 3x3 rotation matrices (Mat9) of the math layer: products, the unit quaternion of a matrix and
// back, the slerp between two orientations, the rotation of a rotation vector and the axis and angle of a
// matrix. The MBDyn coupling's orientations (MBDyn sends row-major matrices) use them; sums in index order.
#pragma once

#include "math/quaternion.h"
#include "math/vec3.h"

#include <cmath>

namespace dembridge::math {

using Mat9 = std::array<double, 9>;

// R v and Rᵀ v
inline Vec3 mat_vec(const Mat9 &R, const double *v)
{
  return {R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
          R[6] * v[0] + R[7] * v[1] + R[8] * v[2]};
}
inline Vec3 mat_t_vec(const Mat9 &R, const double *v)
{
  return {R[0] * v[0] + R[3] * v[1] + R[6] * v[2], R[1] * v[0] + R[4] * v[1] + R[7] * v[2],
          R[2] * v[0] + R[5] * v[1] + R[8] * v[2]};
}
// A B, each element 0 + A_i0 B_0j + A_i1 B_1j + A_i2 B_2j
inline Mat9 mat_mul(const Mat9 &A, const Mat9 &B)
{
  Mat9 C{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) C[3 * i + j] += A[3 * i + k] * B[3 * k + j];
  return C;
}

// The unit quaternion (w, x, y, z) of a rotation matrix (the largest of w, x, y, z computed first), and the
// matrix of a unit quaternion in the 1 - 2(y² + z²) form.
inline Quat quat_of_matrix(const Mat9 &R)
{
  Quat q{};
  const double tr = R[0] + R[4] + R[8];
  if (tr > 0) {
    const double s = 2.0 * std::sqrt(tr + 1.0);
    q = {0.25 * s, (R[7] - R[5]) / s, (R[2] - R[6]) / s, (R[3] - R[1]) / s};
  } else if (R[0] > R[4] && R[0] > R[8]) {
    const double s = 2.0 * std::sqrt(1.0 + R[0] - R[4] - R[8]);
    q = {(R[7] - R[5]) / s, 0.25 * s, (R[1] + R[3]) / s, (R[2] + R[6]) / s};
  } else if (R[4] > R[8]) {
    const double s = 2.0 * std::sqrt(1.0 + R[4] - R[0] - R[8]);
    q = {(R[2] - R[6]) / s, (R[1] + R[3]) / s, 0.25 * s, (R[5] + R[7]) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + R[8] - R[0] - R[4]);
    q = {(R[3] - R[1]) / s, (R[2] + R[6]) / s, (R[5] + R[7]) / s, 0.25 * s};
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double &c : q) c /= n;
  return q;
}
inline Mat9 matrix_of_unit_quat(const Quat &q)
{
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
          2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
          2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
}

// The orientation a fraction s of the way from A to B (s <= 0: A, s >= 1: B), by the shorter arc.
inline Mat9 slerp(const Mat9 &A, const Mat9 &B, double s)
{
  if (s >= 1.0) return B;
  if (s <= 0.0) return A;
  Quat qa = quat_of_matrix(A), qb = quat_of_matrix(B);
  double d = qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3];
  if (d < 0) {
    for (double &c : qb) c = -c;
    d = -d;
  }
  Quat q{};
  if (d > 0.9999995) {
    for (int i = 0; i < 4; ++i) q[i] = qa[i] + s * (qb[i] - qa[i]);
  } else {
    const double th = std::acos(d), st = std::sin(th);
    const double a = std::sin((1 - s) * th) / st, b = std::sin(s * th) / st;
    for (int i = 0; i < 4; ++i) q[i] = a * qa[i] + b * qb[i];
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double &c : q) c /= n;
  return matrix_of_unit_quat(q);
}

// Rotation by the rotation vector th (Rodrigues' formula); the identity below |th| = 1e-300.
inline Mat9 rotation_of_vector(const Vec3 &th)
{
  const double a = std::sqrt(th[0] * th[0] + th[1] * th[1] + th[2] * th[2]);
  if (a < 1e-300) return {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double k[3] = {th[0] / a, th[1] / a, th[2] / a}, s = std::sin(a), c = 1 - std::cos(a);
  return {1 - c * (k[1] * k[1] + k[2] * k[2]), -s * k[2] + c * k[0] * k[1], s * k[1] + c * k[0] * k[2],
          s * k[2] + c * k[0] * k[1], 1 - c * (k[0] * k[0] + k[2] * k[2]), -s * k[0] + c * k[1] * k[2],
          -s * k[1] + c * k[0] * k[2], s * k[0] + c * k[1] * k[2], 1 - c * (k[0] * k[0] + k[1] * k[1])};
}

// Rotation angle and unit axis of R; angle 0 (axis z) when R is the identity, the axis from the largest
// diagonal of (R + I) / 2 at an angle of pi.
inline double axis_angle(const Mat9 &R, Vec3 &axis)
{
  const Vec3 s{R[7] - R[5], R[2] - R[6], R[3] - R[1]};  // 2 sin(a) axis
  const double sn = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  const double c = 0.5 * (R[0] + R[4] + R[8] - 1.0);
  const double a = std::atan2(0.5 * sn, c);
  if (sn > 1e-12) {
    axis = {s[0] / sn, s[1] / sn, s[2] / sn};
    return a;
  }
  if (c > 0) {
    axis = {0, 0, 1};
    return 0.0;
  }
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (R[4 * i] > R[4 * k]) k = i;
  const Vec3 col{R[k] + (k == 0), R[3 + k] + (k == 1), R[6 + k] + (k == 2)};
  const double n = std::sqrt(col[0] * col[0] + col[1] * col[1] + col[2] * col[2]);
  axis = {col[0] / n, col[1] / n, col[2] / n};
  return a;
}

}  // namespace dembridge::math
