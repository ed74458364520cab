// Tangential sub-models (spec granular-models §7): the force Ft on atom i.
#pragma once

#include "contact_geometry.h"

namespace dembridge::gran {

// R: double (one contact) or Lanes4 (four, lane_math.h); branches on values are lane_select,
// which computes both sides (same values as the branches).

// No history (2.x gran/hooke, 3.x tangential no_history): viscous, capped at μ|Fn| (§7.2).
template <class R> [[gnu::always_inline]] inline void tangential_no_history(const ContactGeometryT<R> &g, R gammat, R Ft_max, R *Ft)
{
  const R vrel = len3(g.vtr);
  const R gamma = lane_select(Ft_max < gammat * vrel, Ft_max / vrel, gammat);
  for (int k = 0; k < 3; ++k) Ft[k] = -gamma * g.vtr[k];
}

// Shear history, LIGGGHTS rule (§7.1): damping outside the Coulomb check, none while sliding,
// spring truncated to kt|s| = μ|Fn|. `update` is false in the setup pass (history frozen).
template <class R>
[[gnu::always_inline]] inline void tangential_history(const ContactGeometryT<R> &g, R kt, R gammat, R Ft_max, double dt, bool update, bool projection_2x,
                               R *shear, R *Ft)
{
  if (update) {
    for (int k = 0; k < 3; ++k) shear[k] += g.vtr[k] * dt;
    if (projection_2x) {  // 2.x: (s·del)/rsq · del
      const R rsht = dot3(shear, g.del) * (1.0 / g.rsq);
      for (int k = 0; k < 3; ++k) shear[k] -= rsht * g.del[k];
    } else {
      const R sn = dot3(shear, g.n);
      for (int k = 0; k < 3; ++k) shear[k] -= sn * g.n[k];
    }
  }
  const R shrmag = len3(shear);
  for (int k = 0; k < 3; ++k) Ft[k] = -(kt * shear[k]);
  const R Ft_shear = kt * shrmag;
  const auto slip = Ft_shear > Ft_max, spring = shrmag != 0.0;
  const R ratio = Ft_max / Ft_shear, zero = lane_splat(0.0, kt);
  for (int k = 0; k < 3; ++k) {
    const R slipped = Ft[k] * ratio;
    if (update) shear[k] = lane_select(slip & spring, -slipped / kt, shear[k]);
    Ft[k] = lane_select(slip, lane_select(spring, slipped, zero), Ft[k] - gammat * g.vtr[k]);
  }
}

}  // namespace dembridge::gran
