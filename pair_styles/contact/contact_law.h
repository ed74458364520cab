// A contact law composed of sub-models (normal, damping, tangential; later rolling, cohesion,
// viscous), evaluated for one pair. LAMMPS-free; the pair glue loops over neighbours.
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "contact_result.h"
#include "normal_models.h"
#include "pair_coeffs.h"
#include "cohesion_models.h"
#include "lammps_models.h"
#include "rolling_models.h"
#include "tangential_models.h"

namespace dembridge::gran {

class ContactLaw {
 public:
  explicit ContactLaw(const ContactConfig &cfg = {}) : cfg_(cfg) {}
  const ContactConfig &config() const { return cfg_; }

  // Evaluates the pair (i = a, j = b). Returns false when they do not touch.
  // meff: effective mass after the freeze/rigid rules; history: history_size() doubles or null.
  bool evaluate(const SphereView &a, const SphereView &b, double meff, const PairCoeffs &pc, double *history,
                bool history_update, double dt, ContactResult &out) const;

 private:
  ContactConfig cfg_;
};

// always_inline: the neighbour loop is the hot path; without it GCC stopped inlining once the
// rolling/cohesion/viscous branches were added (+27 % instructions, bench/).
[[gnu::always_inline]] inline bool ContactLaw::evaluate(const SphereView &a, const SphereView &b, double meff, const PairCoeffs &pc,
                                 double *history, bool history_update, double dt, ContactResult &out) const
{
  if (cfg_.lammps_formulation) return evaluate_lammps_gran(cfg_, a, b, meff, pc, history, history_update, dt, out);
  ContactGeometry g;
  if (!make_geometry(a, b, true, g)) return false;
  const NormalCoefficients c = normal_coefficients(cfg_, pc, g, meff);

  double Fn = -c.gamman * g.vn + c.kn * g.delta;
  if (cfg_.limit_force && Fn < 0.0) Fn = 0.0;
  // Cohesion pulls along n; with tangential_reduce (always in 2.x) it also lowers the Coulomb
  // and rolling limits (spec §6).
  double Fcoh = 0.0;
  if (cfg_.cohesion != CohesionModel::Off) Fcoh = cohesion_force(cfg_.cohesion, g, a.radius, b.radius, pc.cohesion_energy_density);
  const double Fn_limit = cfg_.tangential_reduce ? Fn + Fcoh : Fn;
  out.Fn = Fn + Fcoh;
  out.delta = g.delta;

  const double Ft_max = pc.mu * std::fabs(Fn_limit);
  double *Ft = out.Ft;
  double *shear = history;
  switch (cfg_.tangential) {
    case TangentialModel::None: Ft[0] = Ft[1] = Ft[2] = 0.0; break;
    case TangentialModel::NoHistory: tangential_no_history(g, c.gammat, Ft_max, Ft); break;
    case TangentialModel::History:
      tangential_history(g, c.kt, c.gammat, Ft_max, dt, history_update, cfg_.legacy_2x_expressions, shear, Ft);
      break;
  }

  double tor[3];
  cross3(g.n, Ft, tor);
  for (int k = 0; k < 3; ++k) {
    out.F[k] = Fn * g.n[k] + Fcoh * g.n[k] + Ft[k];
    out.Ti[k] = -g.cri * tor[k];
    out.Tj[k] = -g.crj * tor[k];
  }
  if (cfg_.rolling != RollingModel::Off) {
    double *rolling_history = history + (cfg_.tangential == TangentialModel::History ? 3 : 0);
    const RollingInput in{c.kn, c.kt, Fn_limit, pc.mu_roll, pc.eta_roll, pc.roll_stiffness, a.mass, b.mass, a.radius, b.radius};
    double M[3];
    rolling_torque(cfg_, g, a.omega, b.omega, in, dt, history_update, rolling_history, M);
    for (int k = 0; k < 3; ++k) {
      out.Ti[k] -= M[k];
      out.Tj[k] += M[k];
    }
  }
  return true;
}

}  // namespace dembridge::gran
