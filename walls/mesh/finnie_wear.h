// Finnie's erosion model as LIGGGHTS 3.8's fix mesh/surface/stress ... wear finnie applies it to one
// particle-triangle contact in one step (same operations and order). LAMMPS-free.
#pragma once

#include "mesh_vec3.h"

namespace dembridge::mesh {

// Finnie's angle function of the impact angle gamma between the relative velocity and the surface:
// cos^2(gamma)/3 for steep impacts (3 sin > cos, or cos < 0.001), sin(2 gamma) - 3 sin^2(gamma) otherwise
// (LIGGGHTS uses 0.33333 for 1/3).
double finnie_angle_factor(double sin_gamma, double cos_gamma);

// The wear depth one contact adds to a triangle in one step:
//   2 k |v_rel| |F| f(gamma) dt / A
// c = contact point - particle centre, v_rel = v_particle - v_wall, normal = the triangle's unit normal,
// F = the contact force. 0 when the particle moves away from the wall (c . v_rel < 0) or |v_rel| < 1e-7.
double finnie_wear_increment(const Vec3 &c, const Vec3 &v_rel, const Vec3 &normal, double k_finnie,
                             double force_magnitude, double dt, double area);

}  // namespace dembridge::mesh
