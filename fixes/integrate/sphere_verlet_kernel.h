// The velocity-Verlet half steps of finite-size spheres (LAMMPS's fix nve/sphere without dipoles) on flat
// arrays: x, v, f, omega, torque hold 3 doubles per atom. LAMMPS-free; fix_nve_sphere.cpp feeds it.
//
// Every atom gets the built-in's expressions in its order (dtfm = dtf / m; v += dtfm f; x += dtv v;
// dtirotate = dtfrotate / (r r m); omega += dtirotate torque), so the numbers are bitwise the built-in's.
// The AVX2 loop does four atoms of the group at once with the same IEEE operations (divide, multiply, add:
// no FMA, no reordering); a block with an atom outside the group goes atom by atom.
#pragma once

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace dembridge::integrate {

struct SphereArrays {
  double *x, *v, *omega;
  const double *f, *torque, *radius, *rmass;
  const int *mask;
};

struct SphereStep {
  double dtv, dtf, dtfrotate;  // dt, dt/2 in force units, dtf / inertia prefactor
};

// Drift: the first half step (v, omega and x); otherwise the second (v and omega).
template <bool Drift> inline void sphere_step_atom(const SphereArrays &a, const SphereStep &s, int i)
{
  const double dtfm = s.dtf / a.rmass[i];
  for (int c = 0; c < 3; c++) a.v[3 * i + c] += dtfm * a.f[3 * i + c];
  if constexpr (Drift)
    for (int c = 0; c < 3; c++) a.x[3 * i + c] += s.dtv * a.v[3 * i + c];
  const double dtirotate = s.dtfrotate / (a.radius[i] * a.radius[i] * a.rmass[i]);
  for (int c = 0; c < 3; c++) a.omega[3 * i + c] += dtirotate * a.torque[3 * i + c];
}

template <bool Drift> inline void sphere_step_scalar(const SphereArrays &a, const SphereStep &s, int n, int groupbit)
{
  for (int i = 0; i < n; i++)
    if (a.mask[i] & groupbit) sphere_step_atom<Drift>(a, s, i);
}

#if defined(__x86_64__)
// One factor per atom spread over the 12 lanes of its 4 atoms' xyz triples: [f0 f0 f0 f1] [f1 f1 f2 f2] [f2 f3 f3 f3].
struct Spread3 {
  __m256d lo, mid, hi;
};
[[gnu::target("avx2"), gnu::always_inline]] inline Spread3 spread3(__m256d q)
{
  return {_mm256_permute4x64_pd(q, 0x40), _mm256_permute4x64_pd(q, 0xA5), _mm256_permute4x64_pd(q, 0xFE)};
}
// p[0..12) += k * q[0..12), lane by lane
[[gnu::target("avx2"), gnu::always_inline]] inline void add_scaled3(double *p, const Spread3 &k, const double *q)
{
  _mm256_storeu_pd(p, _mm256_add_pd(_mm256_loadu_pd(p), _mm256_mul_pd(k.lo, _mm256_loadu_pd(q))));
  _mm256_storeu_pd(p + 4, _mm256_add_pd(_mm256_loadu_pd(p + 4), _mm256_mul_pd(k.mid, _mm256_loadu_pd(q + 4))));
  _mm256_storeu_pd(p + 8, _mm256_add_pd(_mm256_loadu_pd(p + 8), _mm256_mul_pd(k.hi, _mm256_loadu_pd(q + 8))));
}

template <bool Drift>
[[gnu::target("avx2")]] void sphere_step_avx2(const SphereArrays &a, const SphereStep &s, int n, int groupbit)
{
  const __m256d dtf = _mm256_set1_pd(s.dtf), dtfrotate = _mm256_set1_pd(s.dtfrotate);
  const Spread3 dtv{_mm256_set1_pd(s.dtv), _mm256_set1_pd(s.dtv), _mm256_set1_pd(s.dtv)};
  const __m128i bit = _mm_set1_epi32(groupbit), zero = _mm_setzero_si128();
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m128i in = _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i *>(a.mask + i)), bit);
    if (_mm_movemask_epi8(_mm_cmpeq_epi32(in, zero))) {  // an atom outside the group: one by one
      for (int k = i; k < i + 4; k++)
        if (a.mask[k] & groupbit) sphere_step_atom<Drift>(a, s, k);
      continue;
    }
    const __m256d m = _mm256_loadu_pd(a.rmass + i), r = _mm256_loadu_pd(a.radius + i);
    add_scaled3(a.v + 3 * i, spread3(_mm256_div_pd(dtf, m)), a.f + 3 * i);
    if constexpr (Drift) add_scaled3(a.x + 3 * i, dtv, a.v + 3 * i);
    add_scaled3(a.omega + 3 * i, spread3(_mm256_div_pd(dtfrotate, _mm256_mul_pd(_mm256_mul_pd(r, r), m))), a.torque + 3 * i);
  }
  for (; i < n; i++)
    if (a.mask[i] & groupbit) sphere_step_atom<Drift>(a, s, i);
}
#endif

// The half step of atoms [0, n) of the group: the AVX2 loop where the CPU has it.
template <bool Drift> inline void sphere_step(const SphereArrays &a, const SphereStep &s, int n, int groupbit, bool avx2)
{
#if defined(__x86_64__)
  if (avx2) return sphere_step_avx2<Drift>(a, s, n, groupbit);
#endif
  (void)avx2;
  sphere_step_scalar<Drift>(a, s, n, groupbit);
}

}  // namespace dembridge::integrate
