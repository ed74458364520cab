// 3-vectors of the math layer: std::array triples (Vec3) and the same products on plain double[3]
// (LAMMPS's per-atom arrays, and the four-lane contact law's Lanes4). Every helper spells out its
// operation order: the LIGGGHTS 3.8 and Parmec results are reproduced bit for bit with them.
#pragma once

#include <array>
#include <cmath>
#if defined(__x86_64__) && defined(__GNUC__)
#include <emmintrin.h>
#endif

namespace dembridge::math {

constexpr double kPi = 3.14159265358979323846;

using Vec3 = std::array<double, 3>;

inline Vec3 add(const Vec3 &a, const Vec3 &b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 sub(const Vec3 &a, const Vec3 &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 scale(const Vec3 &a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline Vec3 operator+(const Vec3 &a, const Vec3 &b) { return add(a, b); }
inline Vec3 operator-(const Vec3 &a, const Vec3 &b) { return sub(a, b); }
inline Vec3 operator*(double s, const Vec3 &a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Vec3 &a, const Vec3 &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const double *a, const double *b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline Vec3 cross(const Vec3 &a, const Vec3 &b) { return cross(a.data(), b.data()); }
inline double norm(const Vec3 &a) { return std::sqrt(dot(a, a)); }
// a * (1/s): LIGGGHTS divides vectors by multiplying with the reciprocal.
inline Vec3 div_by(const Vec3 &a, double s)
{
  const double inv = 1.0 / s;
  return {inv * a[0], inv * a[1], inv * a[2]};
}
inline bool all_finite(const Vec3 &a) { return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]); }

// The same products rounded as Parmec's build forms them: its ISPC kernels are compiled with fused
// multiply-add contraction, so x*y + z is fma(x, y, z) (the first product of a sum fused, the other rounded).
inline double dot_fused(const Vec3 &a, const Vec3 &b) { return std::fma(a[2], b[2], std::fma(a[0], b[0], a[1] * b[1])); }
inline Vec3 cross_fused(const Vec3 &a, const Vec3 &b)
{
  return {std::fma(a[1], b[2], -(a[2] * b[1])), std::fma(a[2], b[0], -(a[0] * b[2])), std::fma(a[0], b[1], -(a[1] * b[0]))};
}
// L v, L row-major (Parmec's NVMUL on its column-major storage), each row fma(L2 v2, fma(L1 v1, L0 v0)): the
// spring points p = x + Λ(P − X) of Parmec's spring kernel round this way (the middle product fused first, unlike
// the sums above); replayed against a hung cube's recorded stroke with the recorded positions, every row agrees
// only so (with the first product fused first 4 of 2000 rows differ by an ulp of p).
inline Vec3 rotate_fused(const double *L, const Vec3 &v)
{
  return {std::fma(L[2], v[2], std::fma(L[1], v[1], L[0] * v[0])), std::fma(L[5], v[2], std::fma(L[4], v[1], L[3] * v[0])),
          std::fma(L[8], v[2], std::fma(L[7], v[1], L[6] * v[0]))};
}

// On plain arrays; R: double, or the contact law's Lanes4 (pair_styles/contact/lane_math.h).
template <class R> [[gnu::always_inline]] inline R dot3(const R *a, const R *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm3(const double *a) { return std::sqrt(dot3(a, a)); }
template <class R> [[gnu::always_inline]] inline void cross3(const R *a, const R *b, R *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

// row[0..2] += v[0..2] and row[0..2] -= v[0..2] in place (a pair's force or torque into an atom's
// row of LAMMPS's arrays): the first two elements as one SSE2 operation, which rounds each element
// as the scalar one does; the scalar form cost GCC three instructions per element in the pair sinks.
inline void add_into(double *row, const double *v)
{
#if defined(__x86_64__) && defined(__GNUC__)
  _mm_storeu_pd(row, _mm_add_pd(_mm_loadu_pd(row), _mm_loadu_pd(v)));
  row[2] += v[2];
#else
  for (int k = 0; k < 3; k++) row[k] += v[k];
#endif
}
inline void subtract_from(double *row, const double *v)
{
#if defined(__x86_64__) && defined(__GNUC__)
  _mm_storeu_pd(row, _mm_sub_pd(_mm_loadu_pd(row), _mm_loadu_pd(v)));
  row[2] -= v[2];
#else
  for (int k = 0; k < 3; k++) row[k] -= v[k];
#endif
}

}  // namespace dembridge::math
