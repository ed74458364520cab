// The LAMMPS built-in gran/hooke, gran/hooke/history and gran/hertz/history laws (numeric
// pair_style syntax), written from spec granular-models §13 so that loading the plugin never
// changes a LAMMPS deck's numbers: lever arm R (not R − δ/2), damping meff·γ inside the Coulomb
// check, the del-based expressions, hertz scaling of the whole force by sqrt(δ R*).
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "contact_result.h"
#include "pair_coeffs.h"

#include <algorithm>
#include <type_traits>

namespace dembridge::gran {

// One touching pair of the LAMMPS laws, with the neighbour loop's del = x_i - x_j and rsq reused.
// Hertz, History and LimitDamping are template arguments so that the neighbour loop has no
// run-time switch per contact (issue 12: the kernel the pair and omp styles call).
template <bool Hertz, bool History, bool LimitDamping>
[[gnu::always_inline]] inline void lammps_gran_touching(const SphereView &a, const SphereView &b, double delx, double dely, double delz,
                                                     double rsq, double meff, const PairCoeffs &pc, double *shear, bool update,
                                                     double dt, ContactResult &out)
{
  const double radi = a.radius, radj = b.radius, radsum = radi + radj;
  const double r = std::sqrt(rsq), rinv = 1.0 / r, rsqinv = 1.0 / rsq;
  const double vr1 = a.v[0] - b.v[0], vr2 = a.v[1] - b.v[1], vr3 = a.v[2] - b.v[2];
  const double vnnr = vr1 * delx + vr2 * dely + vr3 * delz;
  const double vt1 = vr1 - delx * vnnr * rsqinv, vt2 = vr2 - dely * vnnr * rsqinv, vt3 = vr3 - delz * vnnr * rsqinv;
  const double wr1 = (radi * a.omega[0] + radj * b.omega[0]) * rinv;
  const double wr2 = (radi * a.omega[1] + radj * b.omega[1]) * rinv;
  const double wr3 = (radi * a.omega[2] + radj * b.omega[2]) * rinv;

  const double damp = meff * pc.gamman * vnnr * rsqinv;
  double ccel = pc.kn * (radsum - r) * rinv - damp;
  double polyhertz = 1.0;
  if constexpr (Hertz) {
    polyhertz = std::sqrt((radsum - r) * radi * radj / radsum);
    ccel *= polyhertz;
  }
  if (LimitDamping && ccel < 0.0) ccel = 0.0;

  const double vtr1 = vt1 - (delz * wr2 - dely * wr3);
  const double vtr2 = vt2 - (delx * wr3 - delz * wr1);
  const double vtr3 = vt3 - (dely * wr1 - delx * wr2);

  double fs1, fs2, fs3;
  if constexpr (History) {
    if (update) {
      shear[0] += vtr1 * dt;
      shear[1] += vtr2 * dt;
      shear[2] += vtr3 * dt;
    }
    const double shrmag = std::sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);
    // rotate the shear displacement into the current tangent plane
    const double rsht = (shear[0] * delx + shear[1] * dely + shear[2] * delz) * rsqinv;
    if (update) {
      shear[0] -= rsht * delx;
      shear[1] -= rsht * dely;
      shear[2] -= rsht * delz;
    }
    const double mg = meff * pc.gammat;
    fs1 = -polyhertz * (pc.kt * shear[0] + mg * vtr1);
    fs2 = -polyhertz * (pc.kt * shear[1] + mg * vtr2);
    fs3 = -polyhertz * (pc.kt * shear[2] + mg * vtr3);
    // Coulomb check on the total (spring + damping) force; slip rescales the spring
    const double fs = std::sqrt(fs1 * fs1 + fs2 * fs2 + fs3 * fs3);
    const double fn = pc.mu * std::fabs(ccel * r);
    if (fs > fn) {
      if (shrmag != 0.0) {
        const double ratio = fn / fs;
        shear[0] = ratio * (shear[0] + mg * vtr1 / pc.kt) - mg * vtr1 / pc.kt;
        shear[1] = ratio * (shear[1] + mg * vtr2 / pc.kt) - mg * vtr2 / pc.kt;
        shear[2] = ratio * (shear[2] + mg * vtr3 / pc.kt) - mg * vtr3 / pc.kt;
        fs1 *= ratio;
        fs2 *= ratio;
        fs3 *= ratio;
      } else {
        fs1 = fs2 = fs3 = 0.0;
      }
    }
  } else {
    const double vrel = std::sqrt(vtr1 * vtr1 + vtr2 * vtr2 + vtr3 * vtr3);
    const double fn = pc.mu * std::fabs(ccel * r);
    const double fs = meff * pc.gammat * vrel;
    const double ft = vrel != 0.0 ? std::min(fn, fs) / vrel : 0.0;
    fs1 = -ft * vtr1;
    fs2 = -ft * vtr2;
    fs3 = -ft * vtr3;
  }

  out.F[0] = delx * ccel + fs1;
  out.F[1] = dely * ccel + fs2;
  out.F[2] = delz * ccel + fs3;
  const double tor1 = rinv * (dely * fs3 - delz * fs2);
  const double tor2 = rinv * (delz * fs1 - delx * fs3);
  const double tor3 = rinv * (delx * fs2 - dely * fs1);
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
