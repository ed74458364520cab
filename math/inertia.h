// Inertia tensors of the math layer (row-major Mat9, rotation.h): Parmec's six-number list, the solid
// sphere and box, point masses and the parallel-axis shift, the inverse in Parmec's operation order, the
// positive-definite test and the principal moments. Every Parmec body (fix parmec/spring, parmec/torsion,
// parmec/rigid, through state::BodyInertia) takes its tensor and inverse from here.
#pragma once

#include "math/rotation.h"
#include "math/vec3.h"

#include <algorithm>
#include <cmath>

namespace dembridge::math {

// Parmec's list [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] as the symmetric tensor.
inline Mat9 inertia_from_list(const double *s) { return {s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2]}; }

// A solid sphere about its centre, (2/5) m r² written 0.4 * m * r * r (the order the fixes always used).
inline double sphere_moment(double mass, double radius) { return 0.4 * mass * radius * radius; }
inline Mat9 sphere_inertia(double mass, double radius)
{
  const double J = sphere_moment(mass, radius);
  return {J, 0, 0, 0, J, 0, 0, 0, J};
}

// A solid box of edges (a, b, c) along x, y, z about its centre: m (b² + c²) / 12, ...
inline Mat9 box_inertia(double mass, const Vec3 &e)
{
  const double m = mass / 12.0, a2 = e[0] * e[0], b2 = e[1] * e[1], c2 = e[2] * e[2];
  return {m * (b2 + c2), 0, 0, 0, m * (a2 + c2), 0, 0, 0, m * (a2 + b2)};
}

// A point mass m at r about the origin, m (|r|² I − r rᵀ): summed over particles, the tensor of a clump.
inline Mat9 point_inertia(double mass, const Vec3 &r)
{
  const double r2 = dot(r, r);
  Mat9 J;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) J[3 * i + j] = mass * ((i == j ? r2 : 0.0) - r[i] * r[j]);
  return J;
}

// Parallel-axis shift: the tensor about a point at d from the centre of mass, Jc + m (|d|² I − d dᵀ).
inline Mat9 parallel_axis(const Mat9 &Jc, double mass, const Vec3 &d)
{
  const Mat9 P = point_inertia(mass, d);
  Mat9 J;
  for (int k = 0; k < 9; ++k) J[k] = Jc[k] + P[k];
  return J;
}

// Inverse by cofactors in Parmec's operation order (its INVERT macro on column-major f: the determinant
// expanded along the first column, each cofactor times 1/det), so that J⁻¹ and everything integrated with
// it agree bitwise with Parmec's.
inline Mat9 inverse_parmec(const Mat9 &J)
{
  const double f0 = J[0], f1 = J[3], f2 = J[6], f3 = J[1], f4 = J[4], f5 = J[7], f6 = J[2], f7 = J[5], f8 = J[8];
  const double det = f0 * (f4 * f8 - f5 * f7) + f3 * (f2 * f7 - f1 * f8) + (f1 * f5 - f2 * f4) * f6;
  const double d = 1.0 / det;
  return {(f4 * f8 - f5 * f7) * d, (f5 * f6 - f3 * f8) * d, (f3 * f7 - f4 * f6) * d,
          (f2 * f7 - f1 * f8) * d, (f0 * f8 - f2 * f6) * d, (f1 * f6 - f0 * f7) * d,
          (f1 * f5 - f2 * f4) * d, (f2 * f3 - f0 * f5) * d, (f0 * f4 - f1 * f3) * d};
}

// The determinant expanded along the first row.
inline double determinant(const Mat9 &J)
{
  return J[0] * (J[4] * J[8] - J[5] * J[7]) - J[1] * (J[3] * J[8] - J[5] * J[6]) + J[2] * (J[3] * J[7] - J[4] * J[6]);
}

// J⁻¹ of a body: 1/J on a diagonal tensor (no cofactor rounding: spheres), else inverse_parmec; zero where
// J is zero or singular (a body without inertia).
inline Mat9 inverse_inertia(const Mat9 &J)
{
  Mat9 inv{};
  if (J[1] == 0.0 && J[2] == 0.0 && J[5] == 0.0) {
    for (int c = 0; c < 3; c++) inv[4 * c] = J[4 * c] > 0.0 ? 1.0 / J[4 * c] : 0.0;
    return inv;
  }
  if (determinant(J) > 0.0) inv = inverse_parmec(J);
  return inv;
}

// Sylvester's criterion on a symmetric tensor: three positive principal moments.
inline bool positive_definite(const Mat9 &J)
{
  return J[0] > 0.0 && J[0] * J[4] - J[1] * J[3] > 0.0 && determinant(J) > 0.0;
}

// The principal moments of a symmetric tensor, ascending (the trigonometric closed form of the symmetric
// 3x3 eigenvalue problem).
inline Vec3 principal_moments(const Mat9 &J)
{
  const double p1 = J[1] * J[1] + J[2] * J[2] + J[5] * J[5];
  const double q = (J[0] + J[4] + J[8]) / 3.0;
  if (p1 == 0.0) {
    Vec3 d{J[0], J[4], J[8]};
    std::sort(d.begin(), d.end());
    return d;
  }
  const double a = J[0] - q, b = J[4] - q, c = J[8] - q;
  const double p = std::sqrt((a * a + b * b + c * c + 2.0 * p1) / 6.0);
  const Mat9 B = {a / p, J[1] / p, J[2] / p, J[3] / p, b / p, J[5] / p, J[6] / p, J[7] / p, c / p};
  const double r = std::clamp(determinant(B) / 2.0, -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  const double big = q + 2.0 * p * std::cos(phi), small = q + 2.0 * p * std::cos(phi + 2.0 * kPi / 3.0);
  return {small, 3.0 * q - big - small, big};
}

}  // namespace dembridge::math
