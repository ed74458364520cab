// Rolling-friction sub-models (spec granular-models §8): a torque M with torque_i −= M, torque_j += M.
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"

#include <type_traits>

namespace dembridge::gran {

template <class R> struct RollingInputT {
  R kn, kt;       // the normal model's stiffnesses of this contact
  R Fn_limit;     // normal force bounding the spring torque (incl. cohesion with tangential_reduce)
  R mu_r, eta_r;  // coefficientRollingFriction, coefficientRollingViscousDamping
  R roll_stiffness;  // epsd3: rollingStiffness
  R mi, mj, Ri, Rj;
  bool wall = false;  // particle-wall contact: wall lever arms and inertia (spec liggghts-walls §2)
  R cr = {};          // lever arm R_i - δ/2 (the 2.x cdt wall torque uses it)
};
using RollingInput = RollingInputT<double>;

// Whether rolling_torque has a lane form (Lanes4) for this model: all but cdt.
constexpr bool rolling_has_lanes(RollingModel m) { return m != RollingModel::Cdt; }

// history: the stored spring torque (3 values) for epsd/epsd2/epsd3, untouched when !update.
// R: double, or Lanes4 (lane_math.h) for the models of rolling_has_lanes.
template <class R>
[[gnu::always_inline]] inline void rolling_torque(const ContactConfig &cfg, const ContactGeometryT<R> &g, const R *wi, const R *wj, const RollingInputT<R> &in,
                           double dt, bool update, R *history, R *M)
{
  const R *n = g.n;
  R wroll[3] = {wi[0] - wj[0], wi[1] - wj[1], wi[2] - wj[2]};
  M[0] = M[1] = M[2] = lane_splat(0.0, in.kn);
  if constexpr (std::is_same_v<R, double>) {
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
  }
  R wt[3];
  if (cfg.torsion_torque) {
    for (int k = 0; k < 3; ++k) wt[k] = wroll[k];
  } else {
    const R d = wroll[0] * n[0] + wroll[1] * n[1] + wroll[2] * n[2];
    for (int k = 0; k < 3; ++k) wt[k] = wroll[k] - n[k] * d;
  }
  R kr;  // left to right, as 3.8 rounds them
  if (cfg.rolling == RollingModel::Epsd) kr = 2.25 * in.kn * in.mu_r * in.mu_r * g.reff * g.reff;
  else if (cfg.rolling == RollingModel::Epsd2) kr = in.kt * g.reff * g.reff;
  else kr = in.roll_stiffness * in.kn * in.mu_r * in.mu_r * g.reff * g.reff;
  for (int k = 0; k < 3; ++k) M[k] = history[k] + wt[k] * (dt * kr);
  const R mag = lane_sqrt(M[0] * M[0] + M[1] * M[1] + M[2] * M[2]);
  const R mx = lane_fabs(in.Fn_limit) * g.reff * in.mu_r;
  const auto slip = mag > mx;  // full mobilisation: the spring slips, no dashpot
  const R fac = mx / mag;
  for (int k = 0; k < 3; ++k) M[k] = lane_select(slip, M[k] * fac, M[k]);
  if (update)
    for (int k = 0; k < 3; ++k) history[k] = M[k];
  if (cfg.rolling != RollingModel::Epsd2) {
    const R ii = in.mi * in.Ri * in.Ri, jj = in.mj * in.Rj * in.Rj;
    // 3D: (1/(I_i + m_iR_i²) + 1/(I_j + m_jR_j²))⁻¹; a wall has infinite inertia: 1.4 m_i R_i²
    const R inertia = in.wall ? 1.4 * in.mi * in.Ri * in.Ri : 1.4 * ii * jj / (ii + jj);
    const R c = in.eta_r * 2 * lane_sqrt(inertia * kr);
    for (int k = 0; k < 3; ++k) M[k] = lane_select(slip, M[k], M[k] + c * wt[k]);
  }
}

}  // namespace dembridge::gran
