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
  static constexpr int kCapacity = kBatch + 4;  // a 4-wide scan step may start at kBatch - 1 and stores four lanes; padding to 4
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
  template <bool WithHistory, bool ClearSeparated>
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
// Left-packing of the touching lanes (a 4-bit mask) without branches: for each mask, the permutation
// that moves the set lanes, in order, to the front (of four doubles as eight 32-bit elements, and of
// four ints). The scan stores all four lanes packed and advances the batch by the number touching:
// which lanes touch is close to random, so a branch per lane (or per group) was mispredicted often.
struct LanePack {
  alignas(32) int pd[16][8];   // _mm256_permutevar8x32 indices of four 64-bit lanes
  alignas(16) int epi32[16][4];
  constexpr LanePack() : pd{}, epi32{}
  {
    for (int m = 0; m < 16; m++) {
      int n = 0;
      for (int k = 0; k < 4; k++)
        if ((m >> k) & 1) {
          pd[m][2 * n] = 2 * k;
          pd[m][2 * n + 1] = 2 * k + 1;
          epi32[m][n++] = k;
        }
      for (; n < 4; n++) {
        pd[m][2 * n] = 2 * n;
        pd[m][2 * n + 1] = 2 * n + 1;
        epi32[m][n] = n;
      }
    }
  }
};
inline constexpr LanePack kLanePack{};

struct Avx2Scan {
  [[gnu::always_inline, gnu::target("avx2")]] static __m256d pack_pd(__m256d v, __m256i perm)
  {
    return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), perm));
  }
  [[gnu::always_inline, gnu::target("avx2")]] static __m128i pack_epi32(__m128i v, __m128i perm)
  {
    return _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castsi128_si256(v), _mm256_castsi128_si256(perm)));
  }
  // clear_springs with masked stores: GCC turns the plain loop into a call to memset, and a call
  // anywhere in the scan loop (even on this rare path) made it keep the per-atom vectors and
  // pointers on the stack, reloaded for every four neighbours (about 40 Ir per atom on the chute)
  [[gnu::always_inline, gnu::target("avx2")]] static void clear_springs_avx2(const ScanAtom &s, int jj)
  {
    s.touch_i[jj] = TouchFlag::Separated;
    double *h = s.hist_i + std::size_t(jj) * s.nv;
    const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
    for (int k = 0; k < s.nv; k += 4)
      _mm256_maskstore_pd(h + k, _mm256_cmpgt_epi64(_mm256_set1_epi64x(s.nv - k), lane), _mm256_setzero_pd());
  }
  template <bool WithHistory, bool ClearSeparated>
  [[gnu::always_inline, gnu::target("avx2")]] static void scan(const ScanAtom &s, int &jj_io, Batch &batch)
  {
    const __m256d xi = _mm256_set1_pd(s.xi), yi = _mm256_set1_pd(s.yi), zi = _mm256_set1_pd(s.zi);
    const __m256d radi = _mm256_set1_pd(s.radi);
    const __m128i lane = _mm_setr_epi32(0, 1, 2, 3), neighmask = _mm_set1_epi32(s.neighmask);
    const __m128i i4 = _mm_set1_epi32(s.i), ii4 = _mm_set1_epi32(s.ii);
    int jj = jj_io;
    while (jj < s.jnum && batch.n < kBatch) {
      // the four list entries from jj on; past the list's end (its last 1-3 entries) masked: atom 0
      const __m128i in_list = _mm_cmpgt_epi32(_mm_set1_epi32(s.jnum - jj), lane);
      const unsigned valid = unsigned(_mm_movemask_ps(_mm_castsi128_ps(in_list)));
      const __m128i j4 = _mm_and_si128(_mm_maskload_epi32(s.jlist + jj, in_list), neighmask);
      alignas(16) int js[4];
      _mm_store_si128(reinterpret_cast<__m128i *>(js), j4);
      // row loads and a transpose, not gathers (pair_gran_rows.h)
      __m256d xj, yj, zj;
      load_rows3(s.x + 3 * std::size_t(js[0]), s.x + 3 * std::size_t(js[1]), s.x + 3 * std::size_t(js[2]), s.x + 3 * std::size_t(js[3]), xj,
                 yj, zj);
      const __m256d delx = _mm256_sub_pd(xi, xj), dely = _mm256_sub_pd(yi, yj), delz = _mm256_sub_pd(zi, zj);
      const __m256d radsum = _mm256_add_pd(radi, load_lanes(s.radius + js[0], s.radius + js[1], s.radius + js[2], s.radius + js[3]));
      const __m256d rsq = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(delx, delx), _mm256_mul_pd(dely, dely)), _mm256_mul_pd(delz, delz));
      const unsigned touching = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(rsq, _mm256_mul_pd(radsum, radsum), _CMP_LT_OQ))) & valid;
      if (ClearSeparated) {
        // the four pairs' flags (the history keeps kTouchPadding flags after its last slot)
        std::uint32_t flags;
        std::memcpy(&flags, s.touch_i + jj, 4);
        const __m128i eq = _mm_cmpeq_epi8(_mm_cvtsi32_si128(int(flags)), _mm_set1_epi8(char(TouchFlag::Touching)));
        const unsigned touched_before = unsigned(_mm_movemask_epi8(eq)) & valid;
        for (unsigned sep = touched_before & ~touching; sep; sep &= sep - 1) clear_springs_avx2(s, jj + __builtin_ctz(sep));
      }
      // all four lanes stored, the touching ones first, in list order (capacity: kBatch + 3)
      const int n = batch.n;
      const __m256i pd = _mm256_load_si256(reinterpret_cast<const __m256i *>(kLanePack.pd[touching]));
      const __m128i epi = _mm_load_si128(reinterpret_cast<const __m128i *>(kLanePack.epi32[touching]));
      _mm256_storeu_pd(batch.dx + n, pack_pd(delx, pd));
      _mm256_storeu_pd(batch.dy + n, pack_pd(dely, pd));
      _mm256_storeu_pd(batch.dz + n, pack_pd(delz, pd));
      _mm256_storeu_pd(batch.rsq + n, pack_pd(rsq, pd));
      const __m128i jj4 = _mm_add_epi32(_mm_set1_epi32(jj), lane);
      _mm_storeu_si128(reinterpret_cast<__m128i *>(batch.j + n), pack_epi32(j4, epi));
      _mm_storeu_si128(reinterpret_cast<__m128i *>(batch.jj + n), pack_epi32(jj4, epi));
      _mm_storeu_si128(reinterpret_cast<__m128i *>(batch.i + n), i4);
      _mm_storeu_si128(reinterpret_cast<__m128i *>(batch.ii + n), ii4);
      if constexpr (WithHistory) {
        const __m256i slot = _mm256_add_epi64(_mm256_set1_epi64x(s.slot0 + jj), _mm256_setr_epi64x(0, 1, 2, 3));
        _mm256_storeu_si256(reinterpret_cast<__m256i *>(batch.slot + n), _mm256_permutevar8x32_epi32(slot, pd));
      }
      batch.n = n + __builtin_popcount(touching);
      jj += 4;
    }
    jj_io = jj < s.jnum ? jj : s.jnum;
  }
};
#endif

}  // namespace dembridge::gran::loop_detail
