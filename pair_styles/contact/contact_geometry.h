// Per-contact geometry and relative kinematics (spec granular-models §4).
#pragma once

#include "vec3.h"

namespace dembridge::gran {

struct SphereView {  // one particle of a pair, as LAMMPS stores it
  const double *x, *v, *omega;
  double radius;
  double mass = 0.0;  // particle (or body) mass; used by the rolling dashpot inertia
};

struct ContactGeometry {
  double del[3];     // x_i - x_j
  double rsq, r, rinv;
  double n[3];       // unit normal, from j to i
  double delta;      // overlap R_i + R_j - r
  double vr[3];      // v_i - v_j
  double vn;         // vr . n (negative while approaching)
  double vtr[3];     // tangential relative surface velocity at the contact point
  double cri, crj;   // lever arms
  double reff;       // R* = R_i R_j / (R_i + R_j); walls: R_i
  double wr_wall[3]; // walls only: the "relative rotation" cr·ω_i/r (spec liggghts-walls §2)
};

// vn and the tangential surface velocity vtr from g.vr, g.n, g.del and the spin term wr (spec §4).
inline void surface_velocity(ContactGeometry &g, const double *wr)
{
  g.vn = dot3(g.vr, g.n);
  double vt[3];
  for (int k = 0; k < 3; ++k) vt[k] = g.vr[k] - g.vn * g.n[k];
  g.vtr[0] = vt[0] - (g.del[2] * wr[1] - g.del[1] * wr[2]);
  g.vtr[1] = vt[1] - (g.del[0] * wr[2] - g.del[2] * wr[0]);
  g.vtr[2] = vt[2] - (g.del[1] * wr[0] - g.del[0] * wr[1]);
}

// Geometry of two touching spheres from the centre difference del = x_i - x_j and rsq = |del|²
// the caller's overlap test computed (the neighbour loop reuses them).
// contact_radius_lever: LIGGGHTS lever arm R - δ/2 (true) or LAMMPS's R (false).
[[gnu::always_inline]] inline void make_touching_geometry(const SphereView &a, const SphereView &b, const double *del, double rsq,
                                                        bool contact_radius_lever, ContactGeometry &g)
{
  g.del[0] = del[0];
  g.del[1] = del[1];
  g.del[2] = del[2];
  g.rsq = rsq;
  const double radsum = a.radius + b.radius;
  g.r = std::sqrt(g.rsq);
  g.rinv = 1.0 / g.r;
  for (int k = 0; k < 3; ++k) g.n[k] = g.del[k] * g.rinv;
  for (int k = 0; k < 3; ++k) g.vr[k] = a.v[k] - b.v[k];
  g.delta = radsum - g.r;
  g.cri = contact_radius_lever ? a.radius - 0.5 * g.delta : a.radius;
  g.crj = contact_radius_lever ? b.radius - 0.5 * g.delta : b.radius;
  double wr[3];
  for (int k = 0; k < 3; ++k) wr[k] = (g.cri * a.omega[k] + g.crj * b.omega[k]) * g.rinv;
  surface_velocity(g, wr);
  g.reff = a.radius * b.radius / radsum;
}

// Returns false (and leaves g unfilled) when the spheres do not overlap (strict <).
inline bool make_geometry(const SphereView &a, const SphereView &b, bool contact_radius_lever, ContactGeometry &g)
{
  const double del[3] = {a.x[0] - b.x[0], a.x[1] - b.x[1], a.x[2] - b.x[2]};
  const double rsq = dot3(del, del);
  const double radsum = a.radius + b.radius;
  if (rsq >= radsum * radsum) return false;
  make_touching_geometry(a, b, del, rsq, contact_radius_lever, g);
  return true;
}

}  // namespace dembridge::gran
