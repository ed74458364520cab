// The six LIGGGHTS primitive walls (spec liggghts-walls §3): planes and cylinders along x, y, z,
// both two-sided. LAMMPS-free.
#pragma once

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
  // Wall velocity at the contact for `shear dim v` (spec §3): a conveyor plane or a spinning cylinder.
  void shear_velocity(const double *x, int dim, double v, double *vwall) const;
};

}  // namespace dembridge::walls
