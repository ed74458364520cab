// Normal sub-models: stiffness and damping coefficients of one contact (spec granular-models §5).
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "pair_coeffs.h"

namespace dembridge::gran {

template <class R> struct NormalCoefficientsT {
  R kn, kt, gamman, gammat;  // absolute: force/length and force*time/length
};
using NormalCoefficients = NormalCoefficientsT<double>;

// γn of the hooke model from ln e (spec §5.1): 3.8 form sqrt(4 m* kn ln²e / (ln²e + π²)),
// 2.x form sqrt(4 m* kn / (1 + (π/ln e)²)); equal up to rounding.
template <class R> [[gnu::always_inline]] inline R hooke_gamma(R meff, R kn, R lnE, bool form_2x)
{
  if (form_2x) return lane_sqrt(4. * meff * kn / (1. + (kPi / lnE) * (kPi / lnE)));
  const R lsq = lnE * lnE;
  return lane_sqrt(4. * meff * kn * lsq / (lsq + kPi * kPi));
}

// R: double (one contact) or Lanes4 (four, lane_math.h); branches on values are lane_select.
template <class R>
[[gnu::always_inline]] inline NormalCoefficientsT<R> normal_coefficients(const ContactConfig &cfg, const PairCoeffsT<R> &pc, const ContactGeometryT<R> &g,
                                                  R meff)
{
  NormalCoefficientsT<R> c{};
  switch (cfg.normal) {
    case NormalModel::Hooke: {
      const R sqrtval = lane_sqrt(g.reff);
      const R V = pc.char_vel;
      c.kn = 16. / 15. * sqrtval * pc.Yeff * lane_pow(15. * meff * V * V / (16. * sqrtval * pc.Yeff), 0.2);
      c.kt = cfg.kt_to_kn_user ? c.kn * 0.285714286 : c.kn;
      if (cfg.viscous) {
        // Legendre: e = e_max exp(−St_c/St) with the 3.8 (dimensionally correct) Stokes number,
        // taken with |vn| so that e never exceeds e_max while separating; at vn = 0 the limit
        // ln e → −∞ gives γn = sqrt(4 m* kn) instead of 3.8's NaN (spec §5.5).
        const R St = meff * lane_fabs(g.vn) / (6.0 * kPi * pc.fluid_viscosity * g.reff * g.reff);
        c.gamman = lane_select(St > 0.0, hooke_gamma(meff, c.kn, pc.ln_max_restitution - pc.critical_stokes / St, cfg.legacy_2x_expressions),
                               lane_sqrt(4. * meff * c.kn));
      } else {
        c.gamman = hooke_gamma(meff, c.kn, pc.lnE, cfg.legacy_2x_expressions);
      }
      c.gammat = c.gamman;
      break;
    }
    case NormalModel::Hertz: {
      constexpr double sqrt56 = 0.91287092917527685576;  // sqrt(5/6)
      const R sqrtval = lane_sqrt(g.reff * g.delta);
      const R Sn = 2. * pc.Yeff * sqrtval;
      const R St = 8. * pc.Geff * sqrtval;
      c.kn = 4. / 3. * pc.Yeff * sqrtval;
      c.kt = St;
      c.gamman = -2. * sqrt56 * pc.beta * lane_sqrt(Sn * meff);
      c.gammat = -2. * sqrt56 * pc.beta * lane_sqrt(St * meff);
      break;
    }
    case NormalModel::HookeStiffness:
      c.kn = pc.kn;
      c.kt = pc.kt;
      c.gamman = cfg.absolute_damping ? pc.gamman : meff * pc.gamman;
      c.gammat = cfg.absolute_damping ? pc.gammat : meff * pc.gammat;
      break;
    case NormalModel::HertzStiffness: {
      const R polyhertz = lane_sqrt(g.reff * g.delta);
      c.kn = polyhertz * pc.kn;
      c.kt = polyhertz * pc.kt;
      c.gamman = polyhertz * meff * pc.gamman;
      c.gammat = polyhertz * meff * pc.gammat;
      break;
    }
  }
  if (!cfg.tangential_damping) c.gammat = lane_splat(0.0, meff);
  return c;
}

}  // namespace dembridge::gran
