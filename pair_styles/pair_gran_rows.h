// Per-atom values of four atoms as four-lane vectors without AVX2 gathers (the AVX2 loop of
// pair_gran_loop.h): a gather counts one instruction but costs many cycles (the AVX2 loop executed
// 15-23 % fewer instructions than the scalar loop and still took more time for the Hooke laws,
// issue 12 P1/P2). Instead each atom's 3-vector is loaded as one row (two doubles and one) and
// the four rows are transposed in registers: plain loads and shuffles, no arithmetic, so the
// values are those a gather gives. Never reads past an atom's own three values.
#pragma once

#include <cstddef>
#include <immintrin.h>

namespace dembridge::gran::loop_detail {

#if defined(__x86_64__) && defined(__GNUC__)
// The three-vectors r0[0..2] .. r3[0..2] as x = (r0[0], r1[0], r2[0], r3[0]), y, z (V: __m256d or Lanes4).
template <class V>
[[gnu::always_inline, gnu::target("avx2")]] inline void load_rows3(const double *r0, const double *r1, const double *r2, const double *r3, V &x,
                                                                   V &y, V &z)
{
  const __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r0)), _mm_loadu_pd(r2), 1);  // x0 y0 x2 y2
  const __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r1)), _mm_loadu_pd(r3), 1);  // x1 y1 x3 y3
  x = _mm256_unpacklo_pd(a, b);
  y = _mm256_unpackhi_pd(a, b);
  const __m128d z01 = _mm_loadh_pd(_mm_load_sd(r0 + 2), r1 + 2), z23 = _mm_loadh_pd(_mm_load_sd(r2 + 2), r3 + 2);
  z = _mm256_insertf128_pd(_mm256_castpd128_pd256(z01), z23, 1);
}

// (p0[0], p1[0], p2[0], p3[0])
[[gnu::always_inline, gnu::target("avx2")]] inline __m256d load_lanes(const double *p0, const double *p1, const double *p2, const double *p3)
{
  const __m128d lo = _mm_loadh_pd(_mm_load_sd(p0), p1), hi = _mm_loadh_pd(_mm_load_sd(p2), p3);
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(lo), hi, 1);
}

// The same for atoms idx[0..3]: base[idx[k]], and the rows base + 3 * idx[k]
[[gnu::always_inline, gnu::target("avx2")]] inline __m256d load_lanes_at(const double *base, const int *idx)
{
  return load_lanes(base + idx[0], base + idx[1], base + idx[2], base + idx[3]);
}
template <class V> [[gnu::always_inline, gnu::target("avx2")]] inline void load_rows3_at(const double *base, const int *idx, V *r)
{
  load_rows3(base + 3 * std::size_t(idx[0]), base + 3 * std::size_t(idx[1]), base + 3 * std::size_t(idx[2]), base + 3 * std::size_t(idx[3]),
             r[0], r[1], r[2]);
}
#endif

}  // namespace dembridge::gran::loop_detail
