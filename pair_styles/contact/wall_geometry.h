// Geometry and relative kinematics of one particle-wall contact (spec liggghts-walls §2): the wall
// hands over the overlap and the vector to its closest point; everything else is recomputed from
// them in LIGGGHTS 3.8's order, which the oracle needs for bit-identity.
#pragma once

#include "contact_geometry.h"
#include "vec3.h"

namespace dembridge::gran {

struct WallTouch {
  double dist_minus_r;    // distance centre-wall minus R_i (<= 0 while touching)
  const double *delta;    // closest wall point minus particle centre
  const double *v_wall;   // wall velocity at the contact
};

inline void make_wall_geometry(const SphereView &a, const WallTouch &w, ContactGeometry &g)
{
  const double ov = -w.dist_minus_r;
  for (int k = 0; k < 3; ++k) g.del[k] = -w.delta[k];
  g.rsq = dot3(g.del, g.del);
  g.r = a.radius - ov;  // not |Δ|: recomputed from the overlap
  g.rinv = 1.0 / g.r;
  for (int k = 0; k < 3; ++k) g.n[k] = g.del[k] * g.rinv;
  for (int k = 0; k < 3; ++k) g.vr[k] = a.v[k] - w.v_wall[k];
  g.delta = a.radius - g.r;         // the overlap every law uses
  g.cri = a.radius - 0.5 * ov;      // lever arm from the overlap handed over
  g.crj = 0.0;
  for (int k = 0; k < 3; ++k) g.wr_wall[k] = g.cri * a.omega[k] * g.rinv;
  surface_velocity(g, g.wr_wall);
  g.reff = a.radius;  // infinite wall radius
}

}  // namespace dembridge::gran
