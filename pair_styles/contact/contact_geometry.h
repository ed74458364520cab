// Per-contact geometry and relative kinematics (spec granular-models §4).
#pragma once

#include "vec3.h"

namespace dembridge::gran {

struct SphereView {  // one particle of a pair, as LAMMPS stores it
  const double *x, *v, *omega;
  double radius;
  double mass = 0.0;  // particle (or body) mass; used by the rolling dashpot inertia
};

// R: double (one contact) or Lanes4 (four, lane_math.h)
template <class R> struct ContactGeometryT {
  R del[3];     // x_i - x_j
  R rsq, r, rinv;
  R n[3];       // unit normal, from j to i
  R delta;      // overlap R_i + R_j - r
  R vr[3];      // v_i - v_j
  R vn;         // vr . n (negative while approaching)
  R vtr[3];     // tangential relative surface velocity at the contact point
  R cri, crj;   // lever arms
  R reff;       // R* = R_i R_j / (R_i + R_j); walls: R_i
  R wr_wall[3]; // walls only: the "relative rotation" cr·ω_i/r (spec liggghts-walls §2)
};
using ContactGeometry = ContactGeometryT<double>;

// vn and the tangential surface velocity vtr from g.vr, g.n, g.del and the spin term wr (spec §4).
template <class R> [[gnu::always_inline]] inline void surface_velocity(ContactGeometryT<R> &g, const R *wr)
{
  g.vn = dot3(g.vr, g.n);
  R vt[3];
  for (int k = 0; k < 3; ++k) vt[k] = g.vr[k] - g.vn * g.n[k];
  g.vtr[0] = vt[0] - (g.del[2] * wr[1] - g.del[1] * wr[2]);
  g.vtr[1] = vt[1] - (g.del[0] * wr[2] - g.del[2] * wr[0]);
  g.vtr[2] = vt[2] - (g.del[1] * wr[0] - g.del[0] * wr[1]);
}

// Geometry of two touching spheres from the centre difference del = x_i - x_j and rsq = |del|²
// the caller's overlap test computed (the neighbour loop reuses them); radii, velocities and
// angular velocities of i and j. contact_radius_lever: LIGGGHTS lever arm R - δ/2 (true) or
// LAMMPS's R (false).
template <class R>
[[gnu::always_inline]] inline void touching_geometry(const R *del, R rsq, R radi, R radj, const R *vi, const R *vj, const R *wi,
                                                   const R *wj, bool contact_radius_lever, ContactGeometryT<R> &g)
{
  g.del[0] = del[0];
  g.del[1] = del[1];
  g.del[2] = del[2];
  g.rsq = rsq;
  const R radsum = radi + radj;
  g.r = lane_sqrt(g.rsq);
  g.rinv = 1.0 / g.r;
  for (int k = 0; k < 3; ++k) g.n[k] = g.del[k] * g.rinv;
  for (int k = 0; k < 3; ++k) g.vr[k] = vi[k] - vj[k];
  g.delta = radsum - g.r;
  g.cri = contact_radius_lever ? radi - 0.5 * g.delta : radi;
  g.crj = contact_radius_lever ? radj - 0.5 * g.delta : radj;
  R wr[3];
  for (int k = 0; k < 3; ++k) wr[k] = (g.cri * wi[k] + g.crj * wj[k]) * g.rinv;
  surface_velocity(g, wr);
  g.reff = radi * radj / radsum;
}

[[gnu::always_inline]] inline void make_touching_geometry(const SphereView &a, const SphereView &b, const double *del, double rsq,
                                                        bool contact_radius_lever, ContactGeometry &g)
{
  touching_geometry(del, rsq, a.radius, b.radius, a.v, b.v, a.omega, b.omega, contact_radius_lever, g);
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
