// Cohesion sub-models (spec granular-models §6): an attractive normal force k·A while overlapping.
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "vec3.h"

namespace dembridge::gran {

// R: double or Lanes4 (lane_math.h). Returns the (negative) cohesion force along n on i.
template <class R> [[gnu::always_inline]] inline R cohesion_force(CohesionModel model, const ContactGeometryT<R> &g, R ri, R rj, R energy_density)
{
  const R r = g.r;
  R A;
  if (model == CohesionModel::Sjkr)  // area of the lens-intersection circle, π a²
    A = -kPi / 4 * ((r - ri - rj) * (r + ri - rj) * (r - ri + rj) * (r + ri + rj)) / (r * r);
  else  // sjkr2: 2π (2R*) δ
    A = kPi * 2. * (2. * ri * rj / (ri + rj)) * (ri + rj - r);
  return -energy_density * A;
}

// Wall branch (spec liggghts-walls §2): the contact area is the sphere-plane cap.
template <class R> [[gnu::always_inline]] inline R cohesion_force_wall(CohesionModel model, const ContactGeometryT<R> &g, R ri, R energy_density)
{
  const R r = g.r;
  R A;
  if (model == CohesionModel::Sjkr) A = (ri * ri - r * r) * kPi;
  else A = kPi * 2. * ri * (ri - r);
  return -energy_density * A;
}

}  // namespace dembridge::gran
