// Normal sub-models: stiffness and damping coefficients of one contact (spec granular-models §5).
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "pair_coeffs.h"

namespace dembridge::gran {

struct NormalCoefficients {
  double kn, kt, gamman, gammat;  // absolute: force/length and force*time/length
};

// γn of the hooke model from ln e (spec §5.1): 3.8 form sqrt(4 m* kn ln²e / (ln²e + π²)),
// 2.x form sqrt(4 m* kn / (1 + (π/ln e)²)); equal up to rounding.
inline double hooke_gamma(double meff, double kn, double lnE, bool form_2x)
{
  if (form_2x) return std::sqrt(4. * meff * kn / (1. + (kPi / lnE) * (kPi / lnE)));
  const double lsq = lnE * lnE;
  return std::sqrt(4. * meff * kn * lsq / (lsq + kPi * kPi));
}

inline NormalCoefficients normal_coefficients(const ContactConfig &cfg, const PairCoeffs &pc, const ContactGeometry &g,
                                              double meff)
{
  NormalCoefficients c{};
  switch (cfg.normal) {
    case NormalModel::Hooke: {
      const double sqrtval = std::sqrt(g.reff);
      const double V = pc.char_vel;
      c.kn = 16. / 15. * sqrtval * pc.Yeff * std::pow(15. * meff * V * V / (16. * sqrtval * pc.Yeff), 0.2);
      c.kt = cfg.kt_to_kn_user ? c.kn * 0.285714286 : c.kn;
      if (cfg.viscous) {
        // Legendre: e = e_max exp(−St_c/St) with the 3.8 (dimensionally correct) Stokes number,
        // taken with |vn| so that e never exceeds e_max while separating; at vn = 0 the limit
        // ln e → −∞ gives γn = sqrt(4 m* kn) instead of 3.8's NaN (spec §5.5).
        const double St = meff * std::fabs(g.vn) / (6.0 * kPi * pc.fluid_viscosity * g.reff * g.reff);
        c.gamman = St > 0.0 ? hooke_gamma(meff, c.kn, pc.ln_max_restitution - pc.critical_stokes / St, cfg.legacy_2x_expressions)
                            : std::sqrt(4. * meff * c.kn);
      } else {
        c.gamman = hooke_gamma(meff, c.kn, pc.lnE, cfg.legacy_2x_expressions);
      }
      c.gammat = c.gamman;
      break;
    }
    case NormalModel::Hertz: {
      constexpr double sqrt56 = 0.91287092917527685576;  // sqrt(5/6)
      const double sqrtval = std::sqrt(g.reff * g.delta);
      const double Sn = 2. * pc.Yeff * sqrtval;
      const double St = 8. * pc.Geff * sqrtval;
      c.kn = 4. / 3. * pc.Yeff * sqrtval;
      c.kt = St;
      c.gamman = -2. * sqrt56 * pc.beta * std::sqrt(Sn * meff);
      c.gammat = -2. * sqrt56 * pc.beta * std::sqrt(St * meff);
      break;
    }
    case NormalModel::HookeStiffness:
      c.kn = pc.kn;
      c.kt = pc.kt;
      c.gamman = cfg.absolute_damping ? pc.gamman : meff * pc.gamman;
      c.gammat = cfg.absolute_damping ? pc.gammat : meff * pc.gammat;
      break;
    case NormalModel::HertzStiffness: {
      const double polyhertz = std::sqrt(g.reff * g.delta);
      c.kn = polyhertz * pc.kn;
      c.kt = polyhertz * pc.kt;
      c.gamman = polyhertz * meff * pc.gamman;
      c.gammat = polyhertz * meff * pc.gammat;
      break;
    }
  }
  if (!cfg.tangential_damping) c.gammat = 0.0;
  return c;
}

}  // namespace dembridge::gran
