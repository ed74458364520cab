// The neighbour loop templates behind run_pair_loop (pair_gran_kernel.h); included from there.
// Floating-point expressions are those of the contact laws (contact/), in their order: the loop
// only feeds them the del and rsq of its overlap test. Translation units instantiating it are
// compiled with -fno-tree-slp-vectorize -fno-math-errno (pair_styles/CMakeLists.txt): GCC's SLP
// vectorizer packs the x/y/z lanes with shuffles that cost more instructions than they save, and
// sqrt need not set errno (same result, one branch less per root).
#pragma once

#include "pair_gran_kernel.h"
#include "pair_gran_scan.h"
#include "pair_gran_lanes.h"
#include "pair_gran_window_scan.h"

#include <cmath>
#include <cstdlib>
#include <string_view>
#include <type_traits>

namespace dembridge::gran {
namespace loop_detail {

// Which loop runs (use_avx2_scan): the AVX2 loop wherever the CPU has AVX2, for every model. Since its
// per-atom values are row loads and an in-register transpose instead of gathers (pair_gran_rows.h) it
// takes 0.86-0.93 of the scalar loop's CPU time for all six chute models (before: 1.07-1.35 for the
// Hooke laws, the gathers being one instruction and many cycles each; doc/benchmarks.md). Both loops
// give bit-identical results; DEMBRIDGE_PAIR_SCAN=avx2 or =scalar forces one.

template <bool Hertz, bool History, bool LimitDamping> struct LammpsKernel {
  static constexpr bool kHistory = History;
#ifdef DEMBRIDGE_HAVE_LANE_CONTACTS
  // four pairs at a time in the AVX2 loop (pair_gran_lanes.h)
  static constexpr bool kLanes = true, kMasses = false;
  static constexpr int kLaneHistory = History ? 3 : 0;  // the shear
  static bool lanes_ok(const PairLoopData &d) { return !History || !d.hist || d.nv >= 3; }
  using LaneIn = LammpsPairIn<Lanes4>;  // gathered into directly, no copy
  static constexpr unsigned kCoeffFields = kLammpsCoeffFields;  // the coefficients the lanes gather or broadcast
  [[gnu::always_inline]] static void lanes(const PairLoopData &d, const LaneIn &in, const PairCoeffsT<Lanes4> &pc, Lanes4 *hist,
                                           ContactResultT<Lanes4> &out)
  {
    lammps_gran_law<Hertz, History, LimitDamping>(in, pc, hist, d.history_update, d.dt, out);
  }
#endif
  [[gnu::always_inline]] static void touching(const PairLoopData &d, const SphereView &a, const SphereView &b, const double *del,
                                              double rsq, double meff, const PairCoeffs &pc, double *hist, ContactResult &out)
  {
    lammps_gran_touching<Hertz, History, LimitDamping>(a, b, del[0], del[1], del[2], rsq, meff, pc, hist, d.history_update, d.dt,
                                                        out);
  }
};

// Plain: no rolling and no cohesion (run_pair_loop checks), as compile-time constants: the law then has
// no code for them (which made the four-lane law keep its values on the stack) and the history is the
// shear alone, a constant 3 values (or none) that unrolls the lanes' history loops.
template <NormalModel Normal, TangentialModel Tangential, bool Plain = false> struct LiggghtsKernel {
  static constexpr bool kHistory = true;  // rolling springs may need it whatever the tangential model
  static constexpr int kPlainHistory = Tangential == TangentialModel::History ? 3 : 0;
  [[gnu::always_inline]] static ContactConfig config(const PairLoopData &d)
  {
    ContactConfig cfg = d.law->config();
    if constexpr (Plain) {
      cfg.rolling = RollingModel::Off;
      cfg.cohesion = CohesionModel::Off;
    }
    return cfg;
  }
#ifdef DEMBRIDGE_HAVE_LANE_CONTACTS
  static constexpr bool kLanes = true, kMasses = true;
  static constexpr int kLaneHistory = Plain ? kPlainHistory : -1;  // -1: d.nv (tangential and rolling springs)
  static bool lanes_ok(const PairLoopData &d)
  {
    return liggghts_laws_have_lanes(d.law->config()) && d.nv <= kLaneMaxHistory && (!Plain || !d.hist || d.nv == kPlainHistory);
  }
  using LaneIn = PairLanes;
  static constexpr unsigned kCoeffFields = liggghts_coeff_fields(Normal);
  [[gnu::always_inline]] static void lanes(const PairLoopData &d, const LaneIn &p, const PairCoeffsT<Lanes4> &pc, Lanes4 *hist,
                                           ContactResultT<Lanes4> &out)
  {
    liggghts_pair_law<Normal, Tangential>(config(d), p.del, p.rsq, p.radi, p.radj, p.vi, p.vj, p.wi, p.wj, p.mi, p.mj, p.meff, pc, hist,
                                          d.history_update, d.dt, out);
  }
#else
  static constexpr bool kLanes = false;
#endif
  [[gnu::always_inline]] static void touching(const PairLoopData &d, const SphereView &a, const SphereView &b, const double *del,
                                              double rsq, double meff, const PairCoeffs &pc, double *hist, ContactResult &out)
  {
    liggghts_pair_touching<Normal, Tangential>(config(d), a, b, del, rsq, meff, pc, hist, d.history_update, d.dt, out);
  }
};

// The contact law on the batch's pairs one at a time, in list order; empties the batch.
struct ScalarContacts {
  template <class Kernel> struct State {  // nothing shared between batches
    explicit State(const PairLoopData &) {}
  };
  template <class Kernel, class Sink>
  [[gnu::always_inline]] static PairLoopError run(const PairLoopData &d, Batch &batch, Sink &sink, State<Kernel> &)
  {
    const double *x = d.x, *v = d.v, *omega = d.omega, *radius = d.radius, *rmass = d.rmass;
    const int *type = d.type, *mask = d.mask;
    const double *mass_rigid = d.mass_rigid;
    const int freeze = d.freeze_groupbit, nv = d.nv;
    const bool with_history = Kernel::kHistory && d.hist;
    double scratch[6] = {0, 0, 0, 0, 0, 0};  // history of a model without any (never read)
    const int n = batch.n;
    batch.n = 0;
    for (int c = 0; c < n; c++) {
      const int i = batch.i[c], j = batch.j[c];
      const double radsum = radius[i] + radius[j];
      const double rsq = batch.rsq[c];
      // coincident centres leave the contact normal undefined (the built-ins return NaN)
      if (!(rsq > kCoincident * radsum * radsum)) return {PairLoopError::Coincident, i, j};
      const double mi = (mass_rigid && mass_rigid[i] > 0.0) ? mass_rigid[i] : rmass[i];
      const double mj = (mass_rigid && mass_rigid[j] > 0.0) ? mass_rigid[j] : rmass[j];
      double meff = mi * mj / (mi + mj);
      if (mask[i] & freeze) meff = mj;
      if (mask[j] & freeze) meff = mi;
      if (!std::isfinite(meff)) return {PairLoopError::NoFiniteMass, i, j};
      const SphereView a{x + 3 * i, v + 3 * i, omega + 3 * i, radius[i], mi};
      const SphereView b{x + 3 * j, v + 3 * j, omega + 3 * j, radius[j], mj};
      double *hist = with_history ? d.hist + batch.slot[c] * nv : scratch;
      const double del[3] = {batch.dx[c], batch.dy[c], batch.dz[c]};
      ContactResult res;
      Kernel::touching(d, a, b, del, rsq, meff, d.coeffs[type[i] * d.coeff_stride + type[j]], hist, res);
      if (with_history) d.touch[batch.slot[c]] = TouchFlag::Touching;
      sink(i, j, batch.ii[c], batch.jj[c], res);
    }
    return {};
  }
};

// pair_loop<Kernel>(d, ii_begin, ii_end, sink) with each scan (pair_gran_loop_body.inc): the
// AVX2 one compiled for AVX2 (not FMA: the law's arithmetic stays that of the scalar build) and
// chosen at run time. The body is included twice because GCC will not inline the AVX2 scan into
// a function compiled for the baseline target.
namespace scalar_scan {
using Scan = ScalarScan;
using Contacts = ScalarContacts;
#include "pair_gran_loop_body.inc"
}  // namespace scalar_scan

#ifdef DEMBRIDGE_HAVE_AVX2_SCAN
#pragma GCC push_options
#pragma GCC target("avx2")
namespace avx2_scan {
using Scan = Avx2WindowScan;
#ifdef DEMBRIDGE_HAVE_LANE_CONTACTS
using Contacts = LaneContacts<ScalarContacts>;
#else
using Contacts = ScalarContacts;
#endif
#include "pair_gran_loop_body.inc"
}  // namespace avx2_scan
#pragma GCC pop_options
#endif

// Which loop runs: the AVX2 one where the CPU has AVX2, unless DEMBRIDGE_PAIR_SCAN=scalar (or =avx2)
// forces one (tests and bench/run_chute_bench.py --loops compare the two: same numbers).
inline bool use_avx2_cpu()
{
#ifdef DEMBRIDGE_HAVE_AVX2_SCAN
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
#else
  return false;
#endif
}
inline bool use_avx2_scan()
{
#ifdef DEMBRIDGE_HAVE_AVX2_SCAN
  static const bool avx2 = [] {
    if (!use_avx2_cpu()) return false;
    const char *env = std::getenv("DEMBRIDGE_PAIR_SCAN");
    return !(env && std::string_view(env) == "scalar");
  }();
  return avx2;
#else
  return false;
#endif
}

template <class Kernel, class Sink> PairLoopError pair_loop(const PairLoopData &d, int ii_begin, int ii_end, Sink &sink)
{
#ifdef DEMBRIDGE_HAVE_AVX2_SCAN
  const bool avx2 = d.scan == PairLoopData::Scan::Default ? use_avx2_scan() : d.scan == PairLoopData::Scan::Avx2 && use_avx2_cpu();
  if (avx2) return avx2_scan::pair_loop<Kernel>(d, ii_begin, ii_end, sink);
#endif
  return scalar_scan::pair_loop<Kernel>(d, ii_begin, ii_end, sink);
}

}  // namespace loop_detail

template <class Sink> PairLoopError run_pair_loop(const PairLoopData &d, int ii_begin, int ii_end, Sink &&sink)
{
  using namespace loop_detail;
  using N = NormalModel;
  using T = TangentialModel;
  const ContactConfig &cfg = d.law->config();
  if (cfg.lammps_formulation) {
    const bool hertz = cfg.normal == N::HertzStiffness, history = cfg.tangential == T::History, lim = cfg.limit_damping;
    if (hertz && history)
      return lim ? pair_loop<LammpsKernel<true, true, true>>(d, ii_begin, ii_end, sink)
                 : pair_loop<LammpsKernel<true, true, false>>(d, ii_begin, ii_end, sink);
    if (history)
      return lim ? pair_loop<LammpsKernel<false, true, true>>(d, ii_begin, ii_end, sink)
                 : pair_loop<LammpsKernel<false, true, false>>(d, ii_begin, ii_end, sink);
    if (!hertz)  // gran/hooke
      return lim ? pair_loop<LammpsKernel<false, false, true>>(d, ii_begin, ii_end, sink)
                 : pair_loop<LammpsKernel<false, false, false>>(d, ii_begin, ii_end, sink);
    return lim ? pair_loop<LammpsKernel<true, false, true>>(d, ii_begin, ii_end, sink)
               : pair_loop<LammpsKernel<true, false, false>>(d, ii_begin, ii_end, sink);
  }
  auto by_tangential = [&](auto normal) {
    constexpr N kN = decltype(normal)::value;
    switch (cfg.tangential) {
      case T::None: return pair_loop<LiggghtsKernel<kN, T::None>>(d, ii_begin, ii_end, sink);
      case T::NoHistory: return pair_loop<LiggghtsKernel<kN, T::NoHistory>>(d, ii_begin, ii_end, sink);
      case T::History: break;
    }
    if (cfg.rolling == RollingModel::Off && cfg.cohesion == CohesionModel::Off)
      return pair_loop<LiggghtsKernel<kN, T::History, true>>(d, ii_begin, ii_end, sink);
    return pair_loop<LiggghtsKernel<kN, T::History>>(d, ii_begin, ii_end, sink);
  };
  switch (cfg.normal) {
    case N::Hooke: return by_tangential(std::integral_constant<N, N::Hooke>{});
    case N::Hertz: return by_tangential(std::integral_constant<N, N::Hertz>{});
    case N::HookeStiffness: return by_tangential(std::integral_constant<N, N::HookeStiffness>{});
    case N::HertzStiffness: break;
  }
  return by_tangential(std::integral_constant<N, N::HertzStiffness>{});
}

}  // namespace dembridge::gran
