// Tangential sub-models (spec granular-models §7): the force Ft on atom i.
#pragma once

#include "contact_geometry.h"

namespace dembridge::gran {

// No history (2.x gran/hooke, 3.x tangential no_history): viscous, capped at μ|Fn| (§7.2).
inline void tangential_no_history(const ContactGeometry &g, double gammat, double Ft_max, double *Ft)
{
  const double vrel = len3(g.vtr);
  const double gamma = Ft_max < gammat * vrel ? Ft_max / vrel : gammat;
  for (int k = 0; k < 3; ++k) Ft[k] = -gamma * g.vtr[k];
}

// Shear history, LIGGGHTS rule (§7.1): damping outside the Coulomb check, none while sliding,
// spring truncated to kt|s| = μ|Fn|. `update` is false in the setup pass (history frozen).
inline void tangential_history(const ContactGeometry &g, double kt, double gammat, double Ft_max, double dt,
                               bool update, bool projection_2x, double *shear, double *Ft)
{
  if (update) {
    for (int k = 0; k < 3; ++k) shear[k] += g.vtr[k] * dt;
    if (projection_2x) {  // 2.x: (s·del)/rsq · del
      const double rsht = dot3(shear, g.del) * (1.0 / g.rsq);
      for (int k = 0; k < 3; ++k) shear[k] -= rsht * g.del[k];
    } else {
      const double sn = dot3(shear, g.n);
      for (int k = 0; k < 3; ++k) shear[k] -= sn * g.n[k];
    }
  }
  const double shrmag = len3(shear);
  for (int k = 0; k < 3; ++k) Ft[k] = -(kt * shear[k]);
  const double Ft_shear = kt * shrmag;
  if (Ft_shear > Ft_max) {
    if (shrmag != 0.0) {
      const double ratio = Ft_max / Ft_shear;
      for (int k = 0; k < 3; ++k) Ft[k] *= ratio;
      if (update)
        for (int k = 0; k < 3; ++k) shear[k] = -Ft[k] / kt;
    } else {
      Ft[0] = Ft[1] = Ft[2] = 0.0;
    }
  } else {
    for (int k = 0; k < 3; ++k) Ft[k] -= gammat * g.vtr[k];
  }
}

}  // namespace dembridge::gran
