// The overlap scan of the neighbour loop (pair_gran_loop.h): walks atom i's neighbours from jj on,
// appends the touching ones to a batch (list order) and clears the springs of separated pairs.
// Two versions with the same results: ScalarScan here, atom by atom, and the AVX2 loop's
// Avx2WindowScan (pair_gran_window_scan.h), which tests four list entries at a time across atoms
// (lane-wise IEEE subtract/multiply/add in the scalar order, no FMA), so del and rsq are
// bit-identical to the scalar ones. Most neighbours do not touch, and the scan was about half of
// the pair style's instructions (issue 12, P1/P2; bench/run_chute_bench.py).
#pragma once

#include "pair_gran_kernel.h"
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

  // Scans atoms ilist[ii .. ii_end) from neighbour jj of the first on, until the batch holds kBatch
  // pairs (ii, jj: where the next call goes on) or the atoms end (ii = ii_end).
  template <bool WithHistory, bool ClearSeparated>
  [[gnu::always_inline]] static PairLoopError scan_atoms(const PairLoopData &data, int &ii_io, int &jj_io, int ii_end, Batch &batch)
  {
    const PairLoopData d = data;  // a local copy: stores to the history cannot alias it
    ScanAtom s{d.x, d.radius, nullptr, 0, d.neighmask, d.nv, 0, 0, 0.0, 0.0, 0.0, 0.0, 0, nullptr, nullptr};
    int ii = ii_io, jj = jj_io;
    for (; ii < ii_end; ii++, jj = 0) {
      const int i = d.ilist[ii];
      if (d.type[i] > d.max_type) return {PairLoopError::TypeAfterInit, i, -1};
      s.i = i;
      s.ii = ii;
      s.jnum = d.numneigh[i];
      s.jlist = d.firstneigh[i];
      s.xi = d.x[3 * i];
      s.yi = d.x[3 * i + 1];
      s.zi = d.x[3 * i + 2];
      s.radi = d.radius[i];
      if constexpr (WithHistory) {
        s.slot0 = std::int64_t(d.hist_first[i]);
        s.touch_i = d.touch + d.hist_first[i];
        s.hist_i = d.hist + d.hist_first[i] * d.nv;
      }
      scan<WithHistory, ClearSeparated>(s, jj, batch);
      if (batch.n >= kBatch) break;  // goes on at (ii, jj), also when jj is past atom ii's last neighbour
    }
    ii_io = ii;
    jj_io = jj;
    return {};
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
  [[gnu::always_inline, gnu::target("avx2")]] static __m256d pack_pd(__m256d v, __m256i perm)
  {
    return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), perm));
  }
  [[gnu::always_inline, gnu::target("avx2")]] static __m128i pack_epi32(__m128i v, __m128i perm)
  {
    return _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castsi128_si256(v), _mm256_castsi128_si256(perm)));
  }
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

#endif

}  // namespace dembridge::gran::loop_detail
