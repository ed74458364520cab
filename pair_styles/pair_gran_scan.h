// The overlap scan of the neighbour loop (pair_gran_loop.h): walks atom i's neighbours from jj on,
// appends the touching ones to a batch (list order) and clears the springs of separated pairs.
// Two versions with the same results: ScalarScan, and Avx2Scan, which tests four neighbours at a
// time (coordinates loaded as rows and transposed, lane-wise IEEE subtract/multiply/add in the scalar order, no FMA),
// so del and rsq are bit-identical to the scalar ones. Most neighbours do not touch, and the scan
// was about half of the pair style's instructions (issue 12, P1/P2; bench/run_chute_bench.py).
#pragma once

#include "pair_gran_rows.h"
#include "touch_flag.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <immintrin.h>

namespace dembridge::gran::loop_detail {

// Centre distances below 1e-12 of the radius sum count as coincident (squared here).
constexpr double kCoincident = 1e-24;

// The touching pairs found by the scan, of one or several atoms i, in list order (structure of
// arrays: the AVX2 loop loads four pairs' values at once).
constexpr int kBatch = 32;  // touching pairs evaluated at a time
struct Batch {
  static constexpr int kCapacity = kBatch + 4;  // a 4-wide scan step may start at kBatch - 1; padding to 4
  alignas(32) double dx[kCapacity], dy[kCapacity], dz[kCapacity], rsq[kCapacity];  // x_i - x_j, |x_i - x_j|^2
  alignas(32) std::int64_t slot[kCapacity];  // history slot hist_first[i] + jj (models with history)
  alignas(16) int i[kCapacity], ii[kCapacity], j[kCapacity], jj[kCapacity];
  int n = 0;
  [[gnu::always_inline]] void push(int ii_, int i_, int jj_, int j_, std::int64_t slot_, double delx, double dely, double delz,
                                   double rsq_)
  {
    ii[n] = ii_;
    i[n] = i_;
    jj[n] = jj_;
    j[n] = j_;
    slot[n] = slot_;
    dx[n] = delx;
    dy[n] = dely;
    dz[n] = delz;
    rsq[n] = rsq_;
    n++;
  }
};

// What the scan of atom i reads (set once per i).
struct ScanAtom {
  const double *x, *radius;
  const int *jlist;
  int jnum, neighmask, nv;
  int i, ii;
  double xi, yi, zi, radi;
  std::int64_t slot0;  // history slot of atom i's first neighbour
  TouchFlag *touch_i;  // null: separated pairs are not cleared here
  double *hist_i;      // history of atom i's first neighbour
};

[[gnu::always_inline]] inline void clear_springs(const ScanAtom &s, int jj)
{
  // 2.x and LAMMPS: the springs vanish on separation. 3.8 clears them only on a neighbour
  // rebuild step: until then a separated pair keeps them (kept 'touched', so a rebuild
  // carries them) and a contact resuming meanwhile continues with the old springs.
  s.touch_i[jj] = TouchFlag::Separated;  // the history fix drops untouched springs at the next neighbour rebuild
  double *h = s.hist_i + std::size_t(jj) * s.nv;
  for (int k = 0; k < s.nv; k++) h[k] = 0.0;
}

struct ScalarScan {
  // Scans from jj until the batch holds kBatch pairs or the list ends.
  template <bool ClearSeparated>
  [[gnu::always_inline]] static void scan(const ScanAtom &s, int &jj_io, Batch &batch)
  {
    int jj = jj_io;
    for (; jj < s.jnum && batch.n < kBatch; jj++) {
      const int j = s.jlist[jj] & s.neighmask;
      const double *xj = s.x + 3 * std::size_t(j);
      const double delx = s.xi - xj[0], dely = s.yi - xj[1], delz = s.zi - xj[2];
      const double radsum = s.radi + s.radius[j];
      const double rsq = delx * delx + dely * dely + delz * delz;
      if (rsq < radsum * radsum) batch.push(s.ii, s.i, jj, j, s.slot0 + jj, delx, dely, delz, rsq);
      else if (ClearSeparated && s.touch_i[jj] == TouchFlag::Touching) clear_springs(s, jj);
    }
    jj_io = jj;
  }
};

#if defined(__x86_64__) && defined(__GNUC__)
#define DEMBRIDGE_HAVE_AVX2_SCAN 1
struct Avx2Scan {
  template <bool ClearSeparated>
  [[gnu::always_inline, gnu::target("avx2")]] static void scan(const ScanAtom &s, int &jj_io, Batch &batch)
  {
    const __m256d xi = _mm256_set1_pd(s.xi), yi = _mm256_set1_pd(s.yi), zi = _mm256_set1_pd(s.zi);
    const __m256d radi = _mm256_set1_pd(s.radi);
    int jj = jj_io;
    while (jj < s.jnum && batch.n < kBatch) {
      const int left = s.jnum - jj;
      const int *jl = s.jlist + jj;  // the four neighbours' list entries
      alignas(16) int tail[4] = {0, 0, 0, 0};
      unsigned valid = 0xF, touched_before = 0;  // lanes in the list; lanes whose pair was touching
      if (left >= 4) {
        if (ClearSeparated) {
          std::uint32_t flags;
          std::memcpy(&flags, s.touch_i + jj, 4);
          const __m128i eq = _mm_cmpeq_epi8(_mm_cvtsi32_si128(int(flags)), _mm_set1_epi8(char(TouchFlag::Touching)));
          touched_before = unsigned(_mm_movemask_epi8(eq)) & 0xF;
        }
      } else {  // the list's last 1-3 entries: never read past its end (atom 0 in the unused lanes)
        for (int k = 0; k < left; k++) {
          tail[k] = s.jlist[jj + k];
          if (ClearSeparated && s.touch_i[jj + k] == TouchFlag::Touching) touched_before |= 1u << k;
        }
        jl = tail;
        valid = (1u << left) - 1;
      }
      const int js[4] = {jl[0] & s.neighmask, jl[1] & s.neighmask, jl[2] & s.neighmask, jl[3] & s.neighmask};
      // row loads and a transpose, not gathers (pair_gran_rows.h)
      __m256d xj, yj, zj;
      load_rows3(s.x + 3 * std::size_t(js[0]), s.x + 3 * std::size_t(js[1]), s.x + 3 * std::size_t(js[2]), s.x + 3 * std::size_t(js[3]), xj,
                 yj, zj);
      const __m256d delx = _mm256_sub_pd(xi, xj), dely = _mm256_sub_pd(yi, yj), delz = _mm256_sub_pd(zi, zj);
      const __m256d radsum = _mm256_add_pd(radi, load_lanes(s.radius + js[0], s.radius + js[1], s.radius + js[2], s.radius + js[3]));
      const __m256d rsq = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(delx, delx), _mm256_mul_pd(dely, dely)), _mm256_mul_pd(delz, delz));
      const unsigned touching = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(rsq, _mm256_mul_pd(radsum, radsum), _CMP_LT_OQ))) & valid;
      if (ClearSeparated) {
        for (unsigned sep = touched_before & ~touching & valid; sep; sep &= sep - 1) clear_springs(s, jj + __builtin_ctz(sep));
      }
      if (touching) {
        alignas(32) double dx[4], dy[4], dz[4], rs[4];
        _mm256_store_pd(dx, delx);
        _mm256_store_pd(dy, dely);
        _mm256_store_pd(dz, delz);
        _mm256_store_pd(rs, rsq);
        for (unsigned t = touching; t; t &= t - 1) {
          const int k = __builtin_ctz(t);
          batch.push(s.ii, s.i, jj + k, js[k], s.slot0 + jj + k, dx[k], dy[k], dz[k], rs[k]);
        }
      }
      jj += left >= 4 ? 4 : left;
    }
    jj_io = jj;
  }
};
#endif

}  // namespace dembridge::gran::loop_detail
