// The six LIGGGHTS primitive walls (spec liggghts-walls §3): planes and cylinders along x, y, z,
// both two-sided. LAMMPS-free.
#pragma once

#include <string>

namespace dembridge::walls {

struct PrimitiveWall {
  enum class Shape { Plane, Cylinder };
  Shape shape = Shape::Plane;
  int axis = 2;          // normal axis of a plane, axis of a cylinder (0 = x, 1 = y, 2 = z)
  double pos = 0.0;      // plane position
  double radius = 0.0;   // cylinder radius
  double c1 = 0.0, c2 = 0.0;  // cylinder axis position on the two other axes, in cyclic order
  int wall_type = 1;     // material type of the wall

  // d − R for a sphere at x of radius r, and delta = closest wall point − centre. Returns false
  // for the degenerate on-axis cylinder contact (no defined normal), which LIGGGHTS reports as
  // touching with a 0/0 normal.
  bool distance(const double *x, double r, double &dist_minus_r, double *delta) const;
  // "zplane at 0.004", "zcylinder of radius 0.04 about (0, 0)": for messages.
  std::string describe() const;
  // Wall velocity at the contact for `shear dim v` (spec §3): a conveyor plane or a spinning cylinder.
  void shear_velocity(const double *x, int dim, double v, double *vwall) const;
};

// A contact whose closest wall point lies within 1e-12 of the radius of the sphere's centre (a
// centre on a plane, on a triangle's face or edge): the contact normal Δ/|Δ| is undefined
// (LIGGGHTS 3.8 computes NaN forces). True also for a non-finite Δ.
inline bool normal_undefined(const double *delta, double radius)
{
  const double dd = delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2];
  return !(dd > 1e-24 * radius * radius);
}

}  // namespace dembridge::walls
