// Rolling-friction sub-models (spec granular-models §8): a torque M with torque_i −= M, torque_j += M.
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"

namespace dembridge::gran {

struct RollingInput {
  double kn, kt;       // the normal model's stiffnesses of this contact
  double Fn_limit;     // normal force bounding the spring torque (incl. cohesion with tangential_reduce)
  double mu_r, eta_r;  // coefficientRollingFriction, coefficientRollingViscousDamping
  double roll_stiffness;  // epsd3: rollingStiffness
  double mi, mj, Ri, Rj;
  bool wall = false;  // particle-wall contact: wall lever arms and inertia (spec liggghts-walls §2)
  double cr = 0.0;    // lever arm R_i - δ/2 (the 2.x cdt wall torque uses it)
};

// history: the stored spring torque (3 doubles) for epsd/epsd2/epsd3, untouched when !update.
inline void rolling_torque(const ContactConfig &cfg, const ContactGeometry &g, const double *wi, const double *wj,
                           const RollingInput &in, double dt, bool update, double *history, double *M)
{
  const double *n = g.n;
  double wroll[3] = {wi[0] - wj[0], wi[1] - wj[1], wi[2] - wj[2]};
  M[0] = M[1] = M[2] = 0.0;
  if (cfg.rolling == RollingModel::Cdt) {
    // the direction is normalised with the full |ω_rel| before the torsional part is removed (kept quirk)
    const double mag = std::sqrt(wroll[0] * wroll[0] + wroll[1] * wroll[1] + wroll[2] * wroll[2]);
    if (mag > 0. && in.wall) {  // rmu·(δ·kn)·wr/|wr|·R_i in this operand order (2.x: lever arm cr)
      const double Fel = g.delta * in.kn;
      const double arm = cfg.legacy_2x_expressions ? in.cr : in.Ri;
      for (int k = 0; k < 3; ++k) M[k] = in.mu_r * Fel * wroll[k] / mag * arm;
      if (!cfg.torsion_torque) {
        const double d = M[0] * n[0] + M[1] * n[1] + M[2] * n[2];
        for (int k = 0; k < 3; ++k) M[k] = M[k] - n[k] * d;
      }
    } else if (mag > 0.) {
      const double s = in.mu_r * in.kn * g.delta * g.reff / mag;
      for (int k = 0; k < 3; ++k) M[k] = wroll[k] * s;
      if (!cfg.torsion_torque) {
        const double d = M[0] * n[0] + M[1] * n[1] + M[2] * n[2];
        for (int k = 0; k < 3; ++k) M[k] = M[k] - n[k] * d;
      }
    }
    return;
  }
  double wt[3];
  if (cfg.torsion_torque) {
    for (int k = 0; k < 3; ++k) wt[k] = wroll[k];
  } else {
    const double d = wroll[0] * n[0] + wroll[1] * n[1] + wroll[2] * n[2];
    for (int k = 0; k < 3; ++k) wt[k] = wroll[k] - n[k] * d;
  }
  double kr;  // left to right, as 3.8 rounds them
  if (cfg.rolling == RollingModel::Epsd) kr = 2.25 * in.kn * in.mu_r * in.mu_r * g.reff * g.reff;
  else if (cfg.rolling == RollingModel::Epsd2) kr = in.kt * g.reff * g.reff;
  else kr = in.roll_stiffness * in.kn * in.mu_r * in.mu_r * g.reff * g.reff;
  for (int k = 0; k < 3; ++k) M[k] = history[k] + wt[k] * (dt * kr);
  const double mag = std::sqrt(M[0] * M[0] + M[1] * M[1] + M[2] * M[2]);
  const double mx = std::fabs(in.Fn_limit) * g.reff * in.mu_r;
  if (mag > mx) {  // full mobilisation: the spring slips, no dashpot
    const double fac = mx / mag;
    for (int k = 0; k < 3; ++k) M[k] *= fac;
    if (update)
      for (int k = 0; k < 3; ++k) history[k] = M[k];
  } else {
    if (update)
      for (int k = 0; k < 3; ++k) history[k] = M[k];
    if (cfg.rolling != RollingModel::Epsd2) {
      const double ii = in.mi * in.Ri * in.Ri, jj = in.mj * in.Rj * in.Rj;
      // 3D: (1/(I_i + m_iR_i²) + 1/(I_j + m_jR_j²))⁻¹; a wall has infinite inertia: 1.4 m_i R_i²
      const double inertia = in.wall ? 1.4 * in.mi * in.Ri * in.Ri : 1.4 * ii * jj / (ii + jj);
      const double c = in.eta_r * 2 * std::sqrt(inertia * kr);
      for (int k = 0; k < 3; ++k) M[k] = M[k] + c * wt[k];
    }
  }
}

}  // namespace dembridge::gran
