// The neighbour loop templates behind run_pair_loop (pair_gran_kernel.h); included from there.
// Floating-point expressions are those of the contact laws (contact/), in their order: the loop
// only feeds them the del and rsq of its overlap test. Translation units instantiating it are
// compiled with -fno-tree-slp-vectorize -fno-math-errno (pair_styles/CMakeLists.txt): GCC's SLP
// vectorizer packs the x/y/z lanes with shuffles that cost more instructions than they save, and
// sqrt need not set errno (same result, one branch less per root).
#pragma once

#include "pair_gran_kernel.h"

#include <cmath>
#include <type_traits>

namespace dembridge::gran {
namespace loop_detail {

// Centre distances below 1e-12 of the radius sum count as coincident (squared here).
constexpr double kCoincident = 1e-24;

template <bool Hertz, bool History, bool LimitDamping> struct LammpsKernel {
  static constexpr bool kHistory = History;
  [[gnu::always_inline]] static void touching(const PairLoopData &d, const SphereView &a, const SphereView &b, const double *del,
                                              double rsq, double meff, const PairCoeffs &pc, double *hist, ContactResult &out)
  {
    lammps_gran_touching<Hertz, History, LimitDamping>(a, b, del[0], del[1], del[2], rsq, meff, pc, hist, d.history_update, d.dt,
                                                        out);
  }
};

template <NormalModel Normal, TangentialModel Tangential> struct LiggghtsKernel {
  static constexpr bool kHistory = true;  // rolling springs may need it whatever the tangential model
  [[gnu::always_inline]] static void touching(const PairLoopData &d, const SphereView &a, const SphereView &b, const double *del,
                                              double rsq, double meff, const PairCoeffs &pc, double *hist, ContactResult &out)
  {
    liggghts_pair_touching<Normal, Tangential>(d.law->config(), a, b, del, rsq, meff, pc, hist, d.history_update, d.dt, out);
  }
};

// A touching neighbour found by the scan: its list position, index and centre difference.
struct Touching {
  int jj, j;
  double del[3], rsq;
};
constexpr int kBatch = 32;  // touching neighbours evaluated at a time (in list order)

// The contact law on n touching neighbours of atom i, in list order.
template <class Kernel, class Sink>
[[gnu::always_inline]] inline PairLoopError contacts(const PairLoopData &d, int ii, int i, const Touching *batch, int n, Sink &sink)
{
  const double *x = d.x, *v = d.v, *omega = d.omega, *radius = d.radius, *rmass = d.rmass;
  const int *type = d.type, *mask = d.mask;
  const double *mass_rigid = d.mass_rigid;
  const int freeze = d.freeze_groupbit, nv = d.nv;
  const bool with_history = Kernel::kHistory && d.hist;
  double scratch[6] = {0, 0, 0, 0, 0, 0};  // history of a model without any (never read)

  const bool ifrozen = mask[i] & freeze;
  const double mi = (mass_rigid && mass_rigid[i] > 0.0) ? mass_rigid[i] : rmass[i];
  const SphereView a{x + 3 * i, v + 3 * i, omega + 3 * i, radius[i], mi};
  double *hist_i = with_history ? d.hist + d.hist_first[i] * nv : nullptr;
  TouchFlag *touch_i = with_history ? d.touch + d.hist_first[i] : nullptr;
  const PairCoeffs *coeff_row = d.coeffs + type[i] * d.coeff_stride;

  for (int c = 0; c < n; c++) {
    const Touching &t = batch[c];
    const int j = t.j, jj = t.jj;
    const double radsum = a.radius + radius[j];
    // coincident centres leave the contact normal undefined (the built-ins return NaN)
    if (!(t.rsq > kCoincident * radsum * radsum)) return {PairLoopError::Coincident, i, j};
    const double mj = (mass_rigid && mass_rigid[j] > 0.0) ? mass_rigid[j] : rmass[j];
    double meff = mi * mj / (mi + mj);
    if (ifrozen) meff = mj;
    if (mask[j] & freeze) meff = mi;
    if (!std::isfinite(meff)) return {PairLoopError::NoFiniteMass, i, j};
    const SphereView b{x + 3 * j, v + 3 * j, omega + 3 * j, radius[j], mj};
    double *hist = with_history ? hist_i + jj * nv : scratch;
    ContactResult res;
    Kernel::touching(d, a, b, t.del, t.rsq, meff, coeff_row[type[j]], hist, res);
    if (with_history) touch_i[jj] = TouchFlag::Touching;
    sink(i, j, ii, jj, res);
  }
  return {};
}

// Two passes per atom i: a tight scan of the neighbours for overlaps (most entries are not in
// contact; it also clears the springs of separated pairs), then the contact law on the touching
// ones, in list order, so every force is summed in the order of a single pass. Keeping the law
// out of the scan frees the registers the scan needs (-30 % instructions on the chute).
template <class Kernel, class Sink>
PairLoopError pair_loop(const PairLoopData &data, int ii_begin, int ii_end, Sink &sink)
{
  const PairLoopData d = data;  // a local copy: stores to f or the history cannot alias it
  const double *x = d.x, *radius = d.radius;
  const int *type = d.type;
  const int nv = d.nv, neighmask = d.neighmask, max_type = d.max_type;
  const bool with_history = Kernel::kHistory && d.hist;
  const bool clear_separated = with_history && d.clear_separated;
  Touching batch[kBatch];

  for (int ii = ii_begin; ii < ii_end; ii++) {
    const int i = d.ilist[ii];
    if (type[i] > max_type) return {PairLoopError::TypeAfterInit, i, -1};
    const int jnum = d.numneigh[i];
    const int *jlist = d.firstneigh[i];
    const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2], radi = radius[i];
    TouchFlag *touch_i = clear_separated ? d.touch + d.hist_first[i] : nullptr;
    int jj = 0;
    while (jj < jnum) {
      int n = 0;
      for (; jj < jnum && n < kBatch; jj++) {
        const int j = jlist[jj] & neighmask;
        const double *xj = x + 3 * std::size_t(j);
        const double delx = xi - xj[0], dely = yi - xj[1], delz = zi - xj[2];
        const double radsum = radi + radius[j];
        const double rsq = delx * delx + dely * dely + delz * delz;
        if (rsq < radsum * radsum) {
          batch[n++] = {jj, j, {delx, dely, delz}, rsq};
        } else if (clear_separated && touch_i[jj] == TouchFlag::Touching) {
          // 2.x and LAMMPS: the springs vanish on separation. 3.8 clears them only on a neighbour
          // rebuild step: until then a separated pair keeps them (kept 'touched', so a rebuild
          // carries them) and a contact resuming meanwhile continues with the old springs.
          touch_i[jj] = TouchFlag::Separated;  // the history fix drops untouched springs at the next neighbour rebuild
          double *h = d.hist + (d.hist_first[i] + jj) * nv;
          for (int k = 0; k < nv; k++) h[k] = 0.0;
        }
      }
      if (n) {
        const PairLoopError e = contacts<Kernel>(d, ii, i, batch, n, sink);
        if (e.kind != PairLoopError::None) return e;
      }
    }
  }
  return {};
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
