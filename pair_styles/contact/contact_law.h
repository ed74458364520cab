// A contact law composed of sub-models (normal, damping, tangential; later rolling, cohesion,
// viscous), evaluated for one pair. LAMMPS-free; the pair glue loops over neighbours.
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "contact_result.h"
#include "normal_models.h"
#include "pair_coeffs.h"
#include "lammps_models.h"
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

inline bool ContactLaw::evaluate(const SphereView &a, const SphereView &b, double meff, const PairCoeffs &pc,
                                 double *history, bool history_update, double dt, ContactResult &out) const
{
  if (cfg_.lammps_formulation) return evaluate_lammps_gran(cfg_, a, b, meff, pc, history, history_update, dt, out);
  ContactGeometry g;
  if (!make_geometry(a, b, true, g)) return false;
  const NormalCoefficients c = normal_coefficients(cfg_, pc, g, meff);

  double Fn = -c.gamman * g.vn + c.kn * g.delta;
  if (cfg_.limit_force && Fn < 0.0) Fn = 0.0;
  out.Fn = Fn;
  out.delta = g.delta;

  const double Ft_max = pc.mu * std::fabs(Fn);
  double *Ft = out.Ft;
  switch (cfg_.tangential) {
    case TangentialModel::None: Ft[0] = Ft[1] = Ft[2] = 0.0; break;
    case TangentialModel::NoHistory: tangential_no_history(g, c.gammat, Ft_max, Ft); break;
    case TangentialModel::History:
      tangential_history(g, c.kt, c.gammat, Ft_max, dt, history_update, cfg_.legacy_2x_expressions, history, Ft);
      break;
  }

  double tor[3];
  cross3(g.n, Ft, tor);
  for (int k = 0; k < 3; ++k) {
    out.F[k] = Fn * g.n[k] + Ft[k];
    out.Ti[k] = -g.cri * tor[k];
    out.Tj[k] = -g.crj * tor[k];
  }
  return true;
}

}  // namespace dembridge::gran
