// Minimal 3-vector helpers for the spring kernels (no Eigen in the per-step path).
#pragma once

#include <array>
#include <cmath>

namespace dembridge::springs {

using Vec3 = std::array<double, 3>;

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// The same products rounded as Parmec's build forms them: its ISPC kernels are compiled with fused
// multiply-add contraction, so x*y + z is fma(x, y, z) (the first product of a sum fused, the other rounded).
inline double dot_fused(const Vec3& a, const Vec3& b) {
  return std::fma(a[2], b[2], std::fma(a[0], b[0], a[1] * b[1]));
}
inline Vec3 cross_fused(const Vec3& a, const Vec3& b) {
  return {std::fma(a[1], b[2], -(a[2] * b[1])), std::fma(a[2], b[0], -(a[0] * b[2])),
          std::fma(a[0], b[1], -(a[1] * b[0]))};
}
// L v, L row-major (Parmec's NVMUL on its column-major storage), each row fma(L2 v2, fma(L1 v1, L0 v0)): the
// spring points p = x + Λ(P − X) of Parmec's spring kernel round this way (the middle product fused first, unlike
// the sums above); replayed against the hung cube's STROKE column with the oracle's positions, every row agrees
// only so (with the first product fused first 4 of 2000 rows differ by an ulp of p).
inline Vec3 rotate_fused(const double* L, const Vec3& v) {
  return {std::fma(L[2], v[2], std::fma(L[1], v[1], L[0] * v[0])), std::fma(L[5], v[2], std::fma(L[4], v[1], L[3] * v[0])),
          std::fma(L[8], v[2], std::fma(L[7], v[1], L[6] * v[0]))};
}

}  // namespace dembridge::springs
