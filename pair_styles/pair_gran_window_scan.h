// The AVX2 overlap scan over windows of four atoms (pair_gran_loop.h): tests four neighbour-list
// entries at a time across atom boundaries, instead of four entries of one atom at a time.
// LAMMPS fills its neighbour pages atom after atom, so the lists of consecutive atoms usually follow
// each other in memory, and the history slots (list order) always do: a window is up to four
// consecutive atoms whose lists and slots are contiguous, and each entry's lane takes its atom's
// position and radius from the window's vectors by a permutation. On the chute (3.6 entries per
// atom) the per-atom scan ran about 1.4 four-lane steps per atom, most of them part-empty, plus its
// per-atom set-up; here about one per atom. The pairs, their del and rsq (the same lane-wise IEEE
// operations as the scalar scan, ScalarScan) and their order are the same, so the results are.
#pragma once

#include "pair_gran_rows.h"
#include "pair_gran_scan.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <immintrin.h>

namespace dembridge::gran::loop_detail {

#ifdef DEMBRIDGE_HAVE_AVX2_SCAN
struct Avx2WindowScan {
  // The atoms of one window: lists base[start[k] .. end[k]) (atom k of ilist[ii0 + k]).
  struct Window {
    alignas(16) int i[4], ii[4], start[4], end[4];
    int n = 0;        // atoms in the window (1-4); the rest repeat the last one with empty lists
    const int *base;  // the first atom's list
    std::int64_t slot0 = 0;  // history slot of base[0]
  };

  // Up to four atoms from ii on whose lists (and history slots) follow each other; an atom of a type
  // beyond the table ends the window before it (the error is returned when it comes first).
  template <bool WithHistory>
  [[gnu::always_inline, gnu::target("avx2")]] static bool make_window(const PairLoopData &d, int ii, int ii_end, Window &w)
  {
    const int i0 = d.ilist[ii];
    if (d.type[i0] > d.max_type) return false;
    w.base = d.firstneigh[i0];
    if constexpr (WithHistory) w.slot0 = std::int64_t(d.hist_first[i0]);
    int e = 0, n = 0;
    for (; n < 4 && ii + n < ii_end; n++) {
      const int i = d.ilist[ii + n];
      if (n > 0) {
        if (d.type[i] > d.max_type || d.firstneigh[i] != w.base + e) break;
        if constexpr (WithHistory)
          if (std::int64_t(d.hist_first[i]) != w.slot0 + e) break;
      }
      w.i[n] = i;
      w.ii[n] = ii + n;
      w.start[n] = e;
      e += d.numneigh[i];
      w.end[n] = e;
    }
    w.n = n;
    for (int k = n; k < 4; k++) {
      w.i[k] = w.i[n - 1];
      w.ii[k] = w.ii[n - 1];
      w.start[k] = w.end[k] = e;
    }
    return true;
  }

  [[gnu::always_inline, gnu::target("avx2")]] static __m256d by_lane(__m256d v, __m256i idx8)
  {
    return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), idx8));
  }
  [[gnu::always_inline, gnu::target("avx2")]] static __m128i by_lane(__m128i v, __m128i idx)
  {
    return _mm_castps_si128(_mm_permutevar_ps(_mm_castsi128_ps(v), idx));
  }

  // Scans atoms ilist[ii .. ii_end) from neighbour jj of the first on, until the batch holds kBatch
  // pairs (ii, jj: where the next call goes on) or the atoms end; as scan_atoms (pair_gran_loop_body.inc).
  template <bool WithHistory, bool ClearSeparated>
  [[gnu::always_inline, gnu::target("avx2")]] static PairLoopError scan_atoms(const PairLoopData &data, int &ii_io, int &jj_io, int ii_end,
                                                                              Batch &batch)
  {
    const PairLoopData d = data;  // a local copy: stores to the history cannot alias it
    const __m128i lane = _mm_setr_epi32(0, 1, 2, 3), neighmask = _mm_set1_epi32(d.neighmask);
    const __m128i touching_byte = _mm_set1_epi8(char(TouchFlag::Touching));
    const __m256i lane64 = _mm256_setr_epi64x(0, 1, 2, 3), one64 = _mm256_set1_epi64x(1);
    int ii = ii_io, jj = jj_io;
    Window w;
    while (ii < ii_end && batch.n < kBatch) {
      if (!make_window<WithHistory>(d, ii, ii_end, w)) {
        ii_io = ii;
        jj_io = jj;
        return {PairLoopError::TypeAfterInit, d.ilist[ii], -1};
      }
      __m256d xa, ya, za;
      load_rows3(d.x + 3 * std::size_t(w.i[0]), d.x + 3 * std::size_t(w.i[1]), d.x + 3 * std::size_t(w.i[2]), d.x + 3 * std::size_t(w.i[3]),
                 xa, ya, za);
      const __m256d rada = load_lanes_at(d.radius, w.i);
      const __m128i ia = _mm_load_si128(reinterpret_cast<const __m128i *>(w.i));
      const __m128i iia = _mm_load_si128(reinterpret_cast<const __m128i *>(w.ii));
      const __m128i starta = _mm_load_si128(reinterpret_cast<const __m128i *>(w.start));
      const __m128i e0 = _mm_set1_epi32(w.end[0]), e1 = _mm_set1_epi32(w.end[1]), e2 = _mm_set1_epi32(w.end[2]);
      const int e = w.end[3];
      int f = jj;  // position in the window's entries (jj of its first atom)
      while (f < e && batch.n < kBatch) {
        const __m128i f4 = _mm_add_epi32(_mm_set1_epi32(f), lane);
        const __m128i in_window = _mm_cmpgt_epi32(_mm_set1_epi32(e), f4);
        const unsigned valid = unsigned(_mm_movemask_ps(_mm_castsi128_ps(in_window)));
        // each lane's atom in the window: how many of the first three atoms' lists end at or before it
        const __m128i k4 = _mm_add_epi32(_mm_set1_epi32(3),
                                         _mm_add_epi32(_mm_add_epi32(_mm_cmpgt_epi32(e0, f4), _mm_cmpgt_epi32(e1, f4)), _mm_cmpgt_epi32(e2, f4)));
        const __m256i k2 = _mm256_slli_epi64(_mm256_cvtepi32_epi64(k4), 1);
        const __m256i k8 = _mm256_or_si256(k2, _mm256_slli_epi64(_mm256_add_epi64(k2, one64), 32));  // (2k, 2k + 1) per double lane
        const __m128i j4 = _mm_and_si128(_mm_maskload_epi32(w.base + f, in_window), neighmask);
        alignas(16) int js[4];
        _mm_store_si128(reinterpret_cast<__m128i *>(js), j4);
        __m256d xj, yj, zj;
        load_rows3(d.x + 3 * std::size_t(js[0]), d.x + 3 * std::size_t(js[1]), d.x + 3 * std::size_t(js[2]), d.x + 3 * std::size_t(js[3]), xj,
                   yj, zj);
        const __m256d delx = _mm256_sub_pd(by_lane(xa, k8), xj), dely = _mm256_sub_pd(by_lane(ya, k8), yj),
                      delz = _mm256_sub_pd(by_lane(za, k8), zj);
        const __m256d radsum = _mm256_add_pd(by_lane(rada, k8), load_lanes_at(d.radius, js));
        const __m256d rsq = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(delx, delx), _mm256_mul_pd(dely, dely)), _mm256_mul_pd(delz, delz));
        const unsigned touching = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(rsq, _mm256_mul_pd(radsum, radsum), _CMP_LT_OQ))) & valid;
        const std::int64_t slot = w.slot0 + f;
        if constexpr (ClearSeparated) {
          std::uint32_t flags;
          std::memcpy(&flags, d.touch + slot, 4);  // (the history keeps kTouchPadding flags after its last slot)
          const __m128i eq = _mm_cmpeq_epi8(_mm_cvtsi32_si128(int(flags)), touching_byte);
          const unsigned touched_before = unsigned(_mm_movemask_epi8(eq)) & valid;
          for (unsigned sep = touched_before & ~touching; sep; sep &= sep - 1) {
            const std::int64_t s = slot + __builtin_ctz(sep);
            d.touch[s] = TouchFlag::Separated;
            double *h = d.hist + std::size_t(s) * d.nv;
            for (int k = 0; k < d.nv; k += 4)  // masked stores: a memset call would put the loop's vectors on the stack
              _mm256_maskstore_pd(h + k, _mm256_cmpgt_epi64(_mm256_set1_epi64x(d.nv - k), lane64), _mm256_setzero_pd());
          }
        }
        // all four lanes stored, the touching ones first, in list order (capacity: kBatch + 3)
        const int n = batch.n;
        const __m256i pd = _mm256_load_si256(reinterpret_cast<const __m256i *>(kLanePack.pd[touching]));
        const __m128i epi = _mm_load_si128(reinterpret_cast<const __m128i *>(kLanePack.epi32[touching]));
        _mm256_storeu_pd(batch.dx + n, LanePack::pack_pd(delx, pd));
        _mm256_storeu_pd(batch.dy + n, LanePack::pack_pd(dely, pd));
        _mm256_storeu_pd(batch.dz + n, LanePack::pack_pd(delz, pd));
        _mm256_storeu_pd(batch.rsq + n, LanePack::pack_pd(rsq, pd));
        _mm_storeu_si128(reinterpret_cast<__m128i *>(batch.j + n), LanePack::pack_epi32(j4, epi));
        _mm_storeu_si128(reinterpret_cast<__m128i *>(batch.jj + n), LanePack::pack_epi32(_mm_sub_epi32(f4, by_lane(starta, k4)), epi));
        _mm_storeu_si128(reinterpret_cast<__m128i *>(batch.i + n), LanePack::pack_epi32(by_lane(ia, k4), epi));
        _mm_storeu_si128(reinterpret_cast<__m128i *>(batch.ii + n), LanePack::pack_epi32(by_lane(iia, k4), epi));
        if constexpr (WithHistory) {
          const __m256i s4 = _mm256_add_epi64(_mm256_set1_epi64x(slot), lane64);
          _mm256_storeu_si256(reinterpret_cast<__m256i *>(batch.slot + n), _mm256_permutevar8x32_epi32(s4, pd));
        }
        batch.n = n + __builtin_popcount(touching);
        f += 4;
      }
      if (f >= e) {  // the window is done
        ii += w.n;
        jj = 0;
      } else {  // the batch is full: go on at the atom of entry f
        int k = 0;
        while (k < w.n - 1 && w.end[k] <= f) k++;
        ii += k;
        jj = f - w.start[k];
      }
    }
    ii_io = ii;
    jj_io = jj;
    return {};
  }
};
#endif

}  // namespace dembridge::gran::loop_detail
