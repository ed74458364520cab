// Cohesion sub-models (spec granular-models §6): an attractive normal force k·A while overlapping.
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "vec3.h"

namespace dembridge::gran {

// Returns the (negative) cohesion force along n on i.
inline double cohesion_force(CohesionModel model, const ContactGeometry &g, double ri, double rj, double energy_density)
{
  const double r = g.r;
  double A;
  if (model == CohesionModel::Sjkr)  // area of the lens-intersection circle, π a²
    A = -kPi / 4 * ((r - ri - rj) * (r + ri - rj) * (r - ri + rj) * (r + ri + rj)) / (r * r);
  else  // sjkr2: 2π (2R*) δ
    A = kPi * 2. * (2. * ri * rj / (ri + rj)) * (ri + rj - r);
  return -energy_density * A;
}

// Wall branch (spec liggghts-walls §2): the contact area is the sphere-plane cap.
inline double cohesion_force_wall(CohesionModel model, const ContactGeometry &g, double ri, double energy_density)
{
  const double r = g.r;
  double A;
  if (model == CohesionModel::Sjkr) A = (ri * ri - r * r) * kPi;
  else A = kPi * 2. * ri * (ri - r);
  return -energy_density * A;
}

}  // namespace dembridge::gran
