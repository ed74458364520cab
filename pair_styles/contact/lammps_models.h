// The LAMMPS built-in gran/hooke, gran/hooke/history and gran/hertz/history laws (numeric
// pair_style syntax), written from spec granular-models §13 so that loading the plugin never
// changes a LAMMPS deck's numbers: lever arm R (not R − δ/2), damping meff·γ inside the Coulomb
// check, the del-based expressions, hertz scaling of the whole force by sqrt(δ R*).
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "contact_result.h"
#include "lane_math.h"
#include "pair_coeffs.h"

#include <algorithm>
#include <type_traits>

namespace dembridge::gran {

// What the LAMMPS laws read of one touching pair (R = double), or of four (R = Lanes4, one pair
// per lane; lane_math.h): del = x_i - x_j and its square from the neighbour loop's overlap test.
// Field names as the LIGGGHTS laws' lane input (pair_gran_lanes.h), so that the AVX2 loop gathers
// straight into either. The type pair's coefficients come separately (PairCoeffsT<R>: kn, kt,
// gamman, gammat, mu), so that the AVX2 loop can pass four gathered pairs' or one broadcast set.
template <class R> struct LammpsPairIn {
  R del[3], rsq;
  R radi, radj;
  R vi[3], vj[3], wi[3], wj[3];  // velocities and angular velocities
  R meff;
};
// The coefficients lammps_gran_law reads (mask over PairCoeffFields, pair_coeffs.h).
constexpr unsigned kLammpsCoeffFields =
    coeff_mask(&PairCoeffs::kn, &PairCoeffs::kt, &PairCoeffs::gamman, &PairCoeffs::gammat, &PairCoeffs::mu);

// The law, written once over the number type R. Hertz, History and LimitDamping are template
// arguments so that the neighbour loop has no run-time switch per contact (issue 12). Branches on
// per-pair values are lane_select for Lanes4, and plain branches for double (which skip the slip
// divisions of sticking contacts); both compute the same expressions in the same order.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // R = Lanes4 is only ever inlined into AVX2 code (lane_math.h)
template <bool Hertz, bool History, bool LimitDamping, class R>
[[gnu::always_inline]] inline void lammps_gran_law(const LammpsPairIn<R> &in, const PairCoeffsT<R> &pc, R *shear, bool update, double dt,
                                                 ContactResultT<R> &out)
{
  constexpr bool kScalar = std::is_same_v<R, double>;
  const R delx = in.del[0], dely = in.del[1], delz = in.del[2], rsq = in.rsq;
  const R radi = in.radi, radj = in.radj, radsum = radi + radj;
  const R r = lane_sqrt(rsq), rinv = 1.0 / r, rsqinv = 1.0 / rsq;
  const R vr1 = in.vi[0] - in.vj[0], vr2 = in.vi[1] - in.vj[1], vr3 = in.vi[2] - in.vj[2];
  const R vnnr = vr1 * delx + vr2 * dely + vr3 * delz;
  const R vt1 = vr1 - delx * vnnr * rsqinv, vt2 = vr2 - dely * vnnr * rsqinv, vt3 = vr3 - delz * vnnr * rsqinv;
  const R wr1 = (radi * in.wi[0] + radj * in.wj[0]) * rinv;
  const R wr2 = (radi * in.wi[1] + radj * in.wj[1]) * rinv;
  const R wr3 = (radi * in.wi[2] + radj * in.wj[2]) * rinv;

  const R damp = in.meff * pc.gamman * vnnr * rsqinv;
  R ccel = pc.kn * (radsum - r) * rinv - damp;
  R polyhertz = lane_splat(1.0, r);
  if constexpr (Hertz) {
    polyhertz = lane_sqrt((radsum - r) * radi * radj / radsum);
    ccel *= polyhertz;
  }
  if constexpr (LimitDamping) ccel = lane_select(ccel < 0.0, lane_splat(0.0, r), ccel);

  const R vtr1 = vt1 - (delz * wr2 - dely * wr3);
  const R vtr2 = vt2 - (delx * wr3 - delz * wr1);
  const R vtr3 = vt3 - (dely * wr1 - delx * wr2);

  R fs1, fs2, fs3;
  if constexpr (History) {
    if (update) {
      shear[0] += vtr1 * dt;
      shear[1] += vtr2 * dt;
      shear[2] += vtr3 * dt;
    }
    const R shrmag = lane_sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);
    // rotate the shear displacement into the current tangent plane
    const R rsht = (shear[0] * delx + shear[1] * dely + shear[2] * delz) * rsqinv;
    if (update) {
      shear[0] -= rsht * delx;
      shear[1] -= rsht * dely;
      shear[2] -= rsht * delz;
    }
    const R mg = in.meff * pc.gammat;
    fs1 = -polyhertz * (pc.kt * shear[0] + mg * vtr1);
    fs2 = -polyhertz * (pc.kt * shear[1] + mg * vtr2);
    fs3 = -polyhertz * (pc.kt * shear[2] + mg * vtr3);
    // Coulomb check on the total (spring + damping) force; slip rescales the spring
    const R fs = lane_sqrt(fs1 * fs1 + fs2 * fs2 + fs3 * fs3);
    const R fn = pc.mu * lane_fabs(ccel * r);
    const R vtr[3] = {vtr1, vtr2, vtr3};
    auto slip_spring = [&](const R &ratio, int k, R &spring) { spring = ratio * (shear[k] + mg * vtr[k] / pc.kt) - mg * vtr[k] / pc.kt; };
    if constexpr (kScalar) {
      if (fs > fn) {
        if (shrmag != 0.0) {
          const double ratio = fn / fs;
          for (int k = 0; k < 3; k++) slip_spring(ratio, k, shear[k]);
          fs1 *= ratio;
          fs2 *= ratio;
          fs3 *= ratio;
        } else {
          fs1 = fs2 = fs3 = 0.0;
        }
      }
    } else {
      const auto slip = fs > fn, spring = shrmag != 0.0;
      const R ratio = fn / fs, zero = lane_splat(0.0, r);
      for (int k = 0; k < 3; k++) {
        R slipped;
        slip_spring(ratio, k, slipped);
        shear[k] = lane_select(slip & spring, slipped, shear[k]);
      }
      fs1 = lane_select(slip, lane_select(spring, fs1 * ratio, zero), fs1);
      fs2 = lane_select(slip, lane_select(spring, fs2 * ratio, zero), fs2);
      fs3 = lane_select(slip, lane_select(spring, fs3 * ratio, zero), fs3);
    }
  } else {
    const R vrel = lane_sqrt(vtr1 * vtr1 + vtr2 * vtr2 + vtr3 * vtr3);
    const R fn = pc.mu * lane_fabs(ccel * r);
    const R fs = in.meff * pc.gammat * vrel;
    R ft;
    if constexpr (kScalar) ft = vrel != 0.0 ? std::min(fn, fs) / vrel : 0.0;
    else ft = lane_select(vrel != 0.0, lane_min(fn, fs) / vrel, lane_splat(0.0, r));
    fs1 = -ft * vtr1;
    fs2 = -ft * vtr2;
    fs3 = -ft * vtr3;
  }

  out.F[0] = delx * ccel + fs1;
  out.F[1] = dely * ccel + fs2;
  out.F[2] = delz * ccel + fs3;
  const R tor1 = rinv * (dely * fs3 - delz * fs2);
  const R tor2 = rinv * (delz * fs1 - delx * fs3);
  const R tor3 = rinv * (delx * fs2 - dely * fs1);
  out.Ti[0] = -radi * tor1;
  out.Ti[1] = -radi * tor2;
  out.Ti[2] = -radi * tor3;
  out.Tj[0] = -radj * tor1;
  out.Tj[1] = -radj * tor2;
  out.Tj[2] = -radj * tor3;
  out.Fn = ccel * r;
  out.Ft[0] = fs1;
  out.Ft[1] = fs2;
  out.Ft[2] = fs3;
  out.delta = radsum - r;
}
#pragma GCC diagnostic pop

// One touching pair (scalar): the law on SphereViews, its history in shear[0..2].
template <bool Hertz, bool History, bool LimitDamping>
[[gnu::always_inline]] inline void lammps_gran_touching(const SphereView &a, const SphereView &b, double delx, double dely, double delz,
                                                     double rsq, double meff, const PairCoeffs &pc, double *shear, bool update,
                                                     double dt, ContactResult &out)
{
  const LammpsPairIn<double> in{{delx, dely, delz}, rsq, a.radius, b.radius,
                                {a.v[0], a.v[1], a.v[2]}, {b.v[0], b.v[1], b.v[2]},
                                {a.omega[0], a.omega[1], a.omega[2]}, {b.omega[0], b.omega[1], b.omega[2]},
                                meff};
  PairCoeffs c;  // a local copy: the law's stores to shear cannot alias it (the table's doubles could)
  c.kn = pc.kn;
  c.kt = pc.kt;
  c.gamman = pc.gamman;
  c.gammat = pc.gammat;
  c.mu = pc.mu;
  lammps_gran_law<Hertz, History, LimitDamping>(in, c, shear, update, dt, out);
}


// The whole law for any pair (per-contact output, tests): the overlap test, then the kernel.
inline bool evaluate_lammps_gran(const ContactConfig &cfg, const SphereView &a, const SphereView &b, double meff, const PairCoeffs &pc,
                                 double *shear, bool update, double dt, ContactResult &out)
{
  const double delx = a.x[0] - b.x[0], dely = a.x[1] - b.x[1], delz = a.x[2] - b.x[2];
  const double rsq = delx * delx + dely * dely + delz * delz;
  const double radsum = a.radius + b.radius;
  if (rsq >= radsum * radsum) return false;
  const bool hertz = cfg.normal == NormalModel::HertzStiffness, history = cfg.tangential == TangentialModel::History;
  auto run = [&](auto h, auto hist, auto lim) {
    lammps_gran_touching<decltype(h)::value, decltype(hist)::value, decltype(lim)::value>(a, b, delx, dely, delz, rsq, meff, pc, shear,
                                                                                         update, dt, out);
  };
  using T = std::true_type;
  using F = std::false_type;
  if (hertz) {
    if (history) cfg.limit_damping ? run(T{}, T{}, T{}) : run(T{}, T{}, F{});
    else cfg.limit_damping ? run(T{}, F{}, T{}) : run(T{}, F{}, F{});
  } else {
    if (history) cfg.limit_damping ? run(F{}, T{}, T{}) : run(F{}, T{}, F{});
    else cfg.limit_damping ? run(F{}, F{}, T{}) : run(F{}, F{}, F{});
  }
  return true;
}

}  // namespace dembridge::gran
