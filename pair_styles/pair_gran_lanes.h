// The contact law on a batch of touching pairs four at a time (the AVX2 loop of pair_gran_loop.h;
// LAMMPS and LIGGGHTS laws): each pair's atom data goes into one lane (row loads and a transpose,
// pair_gran_rows.h), the law (lammps_gran_law or liggghts_pair_law over Lanes4, contact/) runs
// lane-wise with the IEEE operations of the scalar code and no FMA, and the results go to the sink
// one pair at a time in list order, so forces are summed as in the scalar loop and results stay
// bit-identical (issue 12, P1/P2). The type pair's coefficients (only the fields the kernel reads,
// Kernel::kCoeffFields) are broadcast once per batch when the table is uniform (one atom type: the
// chute, most decks), else gathered per four pairs.
#pragma once

#include "pair_gran_kernel.h"
#include "pair_gran_rows.h"
#include "pair_gran_scan.h"

#include <cstddef>
#include <cstdint>
#include <immintrin.h>
#include <algorithm>
#include <limits>
#include <type_traits>
#include <utility>

namespace dembridge::gran::loop_detail {

#if defined(DEMBRIDGE_HAVE_AVX2_SCAN) && defined(DEMBRIDGE_HAVE_LANES4)
#define DEMBRIDGE_HAVE_LANE_CONTACTS 1

constexpr int kLaneMaxHistory = 6;  // history values per pair the lanes carry
constexpr int kPrefetchAhead = 8;   // pairs
// The atom data of four touching pairs, one per lane, that the LIGGGHTS laws' lane forms
// read. Kernel::LaneIn is the kernel's own input type (LAMMPS laws: LammpsPairIn<Lanes4>, the same
// field names less mi, mj and the LIGGGHTS coefficients), which the loop fills directly.
struct PairLanes {
  Lanes4 del[3], rsq, radi, radj, vi[3], vj[3], wi[3], wj[3], mi, mj, meff;
};

// The fields of Mask (PairCoeffFields, pair_coeffs.h) of a four-lane coefficient set, each from
// load(&the field in c0): a gather over the type pairs of four lanes, or one broadcast value.
template <unsigned Mask, std::size_t K, class Load>
[[gnu::always_inline, gnu::target("avx2")]] inline void load_coeff(PairCoeffsT<Lanes4> &out, const PairCoeffs &c0, const Load &load)
{
  if constexpr ((Mask >> K) & 1u) {
    constexpr auto lanes_field = PairCoeffFields<Lanes4>::kAll[K];
    constexpr auto field = PairCoeffFields<double>::kAll[K];
    out.*lanes_field = load(&(c0.*field));
  }
}
template <unsigned Mask, class Load, std::size_t... K>
[[gnu::always_inline, gnu::target("avx2")]] inline void load_coeffs(PairCoeffsT<Lanes4> &out, const PairCoeffs &c0, const Load &load, std::index_sequence<K...>)
{
  (load_coeff<Mask, K>(out, c0, load), ...);
}
template <unsigned Mask, class Load> [[gnu::always_inline, gnu::target("avx2")]] inline void load_coeffs(PairCoeffsT<Lanes4> &out, const PairCoeffs &c0, const Load &load)
{
  load_coeffs<Mask>(out, c0, load, std::make_index_sequence<PairCoeffFields<double>::kCount>{});
}

// A sink with prefetch(j) (the serial compute's) can fetch ahead the rows it will add pair j's force to.
template <class Sink, class = void> struct SinkPrefetches : std::false_type {};
template <class Sink>
struct SinkPrefetches<Sink, std::void_t<decltype(std::declval<const Sink &>().prefetch(0))>> : std::true_type {};

// Fallback: the per-pair evaluation, for the kernels without a lane form (Kernel::kLanes false).
template <class Fallback> struct LaneContacts {
  [[gnu::always_inline, gnu::target("avx2")]] static Lanes4 gather(const double *base, __m128i idx)
  {
    return _mm256_mask_i32gather_pd(_mm256_setzero_pd(), base, idx, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), 8);
  }
  [[gnu::always_inline, gnu::target("avx2")]] static __m128i gather(const int *base, __m128i idx)
  {
    return _mm_mask_i32gather_epi32(_mm_setzero_si128(), base, idx, _mm_set1_epi32(-1), 4);
  }
  // the int lanes as 64-bit masks: -1 where the value is nonzero
  [[gnu::always_inline, gnu::target("avx2")]] static LaneMask4 nonzero(__m128i v)
  {
    return (LaneMask4)_mm256_cvtepi32_epi64(v) != 0;
  }
  [[gnu::always_inline, gnu::target("avx2")]] static unsigned bits(LaneMask4 m) { return unsigned(_mm256_movemask_pd((__m256d)m)); }
  // coefficient loads for load_coeffs: four lanes' type pairs (element offsets from the field), or one value
  struct GatherAt {
    __m128i offset;
    [[gnu::always_inline, gnu::target("avx2")]] Lanes4 operator()(const double *field) const { return gather(field, offset); }
  };
  struct Broadcast {
    [[gnu::always_inline, gnu::target("avx2")]] Lanes4 operator()(const double *field) const { return _mm256_broadcast_sd(field); }
  };

  // What the batches of one loop share, set up once per loop (pair_loop): the type pair's coefficients as
  // four lanes, broadcast from the table when it is uniform, and the set the gathers fill. Per batch,
  // value-initialising both (17 fields of 4 lanes each) cost 2.2 Ir per atom-step on the chute.
  template <class Kernel> struct State {
    typename Fallback::template State<Kernel> fallback;
    PairCoeffsT<Lanes4> broadcast, gathered;
    [[gnu::target("avx2")]] explicit State(const PairLoopData &d) : fallback(d)
    {
      if constexpr (Kernel::kLanes)
        if (d.uniform_coeffs) load_coeffs<Kernel::kCoeffFields>(broadcast, d.coeffs[d.coeff_stride + 1], Broadcast{});
    }
  };

  template <class Kernel, class Sink>
  // out of line: inlined, its register demand made the per-atom scan loop spill (about 18 Ir per atom-step)
  [[gnu::noinline, gnu::target("avx2")]] static PairLoopError run(const PairLoopData &d, Batch &b, Sink &sink, State<Kernel> &state)
  {
    if constexpr (!Kernel::kLanes) {
      return Fallback::template run<Kernel>(d, b, sink, state.fallback);
    } else {
      if (!Kernel::lanes_ok(d)) return Fallback::template run<Kernel>(d, b, sink, state.fallback);
      const int n = b.n, n4 = (n + 3) & ~3;
      b.n = 0;
      for (int c = n; c < n4; c++) {  // padding lanes: copies of the last pair (results unused)
        b.dx[c] = b.dx[n - 1];
        b.dy[c] = b.dy[n - 1];
        b.dz[c] = b.dz[n - 1];
        b.rsq[c] = b.rsq[n - 1];
        if (Kernel::kHistory && d.hist) b.slot[c] = b.slot[n - 1];  // (stored by the scan with history only)
        b.i[c] = b.i[n - 1];
        b.j[c] = b.j[n - 1];
      }
      const bool with_history = Kernel::kHistory && d.hist;
      // values per history slot moved through the lanes: a constant where the kernel knows it
      const int nv = Kernel::kLaneHistory >= 0 ? Kernel::kLaneHistory : d.nv;  // a constant unrolls the loops
      constexpr int kF = 0, kTi = 3, kTj = 6, kFn = 9, kFt = 10, kDelta = 13, kHist = 14, kOut = kHist + kLaneMaxHistory;
      alignas(32) double out[kOut][Batch::kCapacity];
      static_assert(sizeof(PairCoeffs) % sizeof(double) == 0);
      const __m128i coeff_stride = _mm_set1_epi32(d.coeff_stride), coeff_doubles = _mm_set1_epi32(int(sizeof(PairCoeffs) / sizeof(double)));
      // One type pair's coefficients for every pair (one atom type, or equal materials): broadcast
      // once per loop (State) instead of gathered per four pairs; the law reads them from memory.
      const bool uniform = d.uniform_coeffs;
      PairCoeffsT<Lanes4> &gathered = state.gathered;
      const PairCoeffsT<Lanes4> &pc = uniform ? state.broadcast : gathered;
      for (int c = 0; c < n4; c += 4) {
        // Two groups ahead, the rows that miss the cache most (perf, chute): the pair's history slot,
        // the neighbour's velocity, spin and mass, and the neighbour's force and torque rows of the sink
        // (the scan has only read the positions; atom i's rows follow the list and stay cached)
        for (int q = c + kPrefetchAhead, q_end = std::min(c + kPrefetchAhead + 4, n); q < q_end; q++) {
          const std::size_t j3 = 3 * std::size_t(b.j[q]);
          if (with_history) __builtin_prefetch(d.hist + b.slot[q] * d.nv, 1);
          __builtin_prefetch(d.v + j3);
          __builtin_prefetch(d.omega + j3);
          if constexpr (SinkPrefetches<Sink>::value) sink.prefetch(b.j[q]);
        }
        // per-atom values as rows and lanes (pair_gran_rows.h), not gathers
        const int *ic = b.i + c, *jc = b.j + c;
        typename Kernel::LaneIn p;
        p.del[0] = _mm256_load_pd(b.dx + c);
        p.del[1] = _mm256_load_pd(b.dy + c);
        p.del[2] = _mm256_load_pd(b.dz + c);
        p.rsq = _mm256_load_pd(b.rsq + c);
        p.radi = load_lanes_at(d.radius, ic);
        p.radj = load_lanes_at(d.radius, jc);
        const Lanes4 radsum = p.radi + p.radj;
        // coincident centres leave the contact normal undefined (the built-ins return NaN)
        const unsigned coincident = ~bits(p.rsq > kCoincident * radsum * radsum) & 0xF;
        Lanes4 mi = load_lanes_at(d.rmass, ic), mj = load_lanes_at(d.rmass, jc);
        if (d.mass_rigid) {
          const Lanes4 bi = load_lanes_at(d.mass_rigid, ic), bj = load_lanes_at(d.mass_rigid, jc);
          mi = lane_select(bi > 0.0, bi, mi);
          mj = lane_select(bj > 0.0, bj, mj);
        }
        Lanes4 meff = mi * mj / (mi + mj);
        if (d.freeze_groupbit) {
          const int *m = d.mask, fz = d.freeze_groupbit;
          meff = lane_select(nonzero(_mm_setr_epi32(m[ic[0]] & fz, m[ic[1]] & fz, m[ic[2]] & fz, m[ic[3]] & fz)), mj, meff);
          meff = lane_select(nonzero(_mm_setr_epi32(m[jc[0]] & fz, m[jc[1]] & fz, m[jc[2]] & fz, m[jc[3]] & fz)), mi, meff);
        }
        const unsigned infinite = ~bits(lane_fabs(meff) <= std::numeric_limits<double>::max()) & 0xF;
        if (coincident | infinite) {
          const int k = __builtin_ctz(coincident | infinite);
          return {(coincident >> k) & 1 ? PairLoopError::Coincident : PairLoopError::NoFiniteMass, b.i[c + k], b.j[c + k]};
        }
        if constexpr (Kernel::kMasses) {  // the LIGGGHTS laws also read the masses
          p.mi = mi;
          p.mj = mj;
        }
        p.meff = meff;
        load_rows3_at(d.v, ic, p.vi);
        load_rows3_at(d.v, jc, p.vj);
        load_rows3_at(d.omega, ic, p.wi);
        load_rows3_at(d.omega, jc, p.wj);
        if (!uniform) {
          const __m128i iv = _mm_load_si128(reinterpret_cast<const __m128i *>(b.i + c));
          const __m128i jv = _mm_load_si128(reinterpret_cast<const __m128i *>(b.j + c));
          const __m128i pair_type = _mm_add_epi32(_mm_mullo_epi32(gather(d.type, iv), coeff_stride), gather(d.type, jv));
          load_coeffs<Kernel::kCoeffFields>(gathered, *d.coeffs, GatherAt{_mm_mullo_epi32(pair_type, coeff_doubles)});
        }
        // (not value-initialised: zeroing all kLaneMaxHistory lanes per four pairs cost 3 Ir per atom-step)
        Lanes4 hist[Kernel::kLaneHistory > 0 ? Kernel::kLaneHistory : Kernel::kLaneHistory == 0 ? 1 : kLaneMaxHistory];
        if (with_history) {  // each pair's nv values in a row: rows of three, then single values
          const double *h0 = d.hist + b.slot[c] * d.nv, *h1 = d.hist + b.slot[c + 1] * d.nv, *h2 = d.hist + b.slot[c + 2] * d.nv,
                       *h3 = d.hist + b.slot[c + 3] * d.nv;
          int k = 0;
          for (; k + 3 <= nv; k += 3) load_rows3(h0 + k, h1 + k, h2 + k, h3 + k, hist[k], hist[k + 1], hist[k + 2]);
          for (; k < nv; k++) hist[k] = load_lanes(h0 + k, h1 + k, h2 + k, h3 + k);
        } else {
          for (Lanes4 &h : hist) h = Lanes4{};  // a model without history values (never read)
        }
        ContactResultT<Lanes4> o;
        Kernel::lanes(d, p, pc, hist, o);
        for (int k = 0; k < 3; k++) {
          _mm256_store_pd(out[kF + k] + c, o.F[k]);
          _mm256_store_pd(out[kTi + k] + c, o.Ti[k]);
          _mm256_store_pd(out[kTj + k] + c, o.Tj[k]);
          _mm256_store_pd(out[kFt + k] + c, o.Ft[k]);
        }
        _mm256_store_pd(out[kFn] + c, o.Fn);
        _mm256_store_pd(out[kDelta] + c, o.delta);
        if (with_history)
          for (int k = 0; k < nv; k++) _mm256_store_pd(out[kHist + k] + c, hist[k]);
      }
      // The history first, then the forces: in one loop, the flag's byte store (which may alias
      // anything) made every pair reload the sink's pointers and d's fields.
      if (with_history) {
        double *const hist_values = d.hist;
        TouchFlag *const touch = d.touch;
        const std::int64_t stride = d.nv;
        for (int c = 0; c < n; c++) {
          const std::int64_t s = b.slot[c];
          double *h = hist_values + s * stride;
          for (int k = 0; k < nv; k++) h[k] = out[kHist + k][c];
          touch[s] = TouchFlag::Touching;
        }
      }
      for (int c = 0; c < n; c++) {
        ContactResult res;
        for (int k = 0; k < 3; k++) {
          res.F[k] = out[kF + k][c];
          res.Ti[k] = out[kTi + k][c];
          res.Tj[k] = out[kTj + k][c];
          res.Ft[k] = out[kFt + k][c];
        }
        res.Fn = out[kFn][c];
        res.delta = out[kDelta][c];
        sink(b.i[c], b.j[c], b.ii[c], b.jj[c], res);
      }
      return {};
    }
  }
};
#endif

}  // namespace dembridge::gran::loop_detail
