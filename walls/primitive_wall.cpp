#include "primitive_wall.h"

#include <cmath>
#include <cstdio>

namespace dembridge::walls {

bool PrimitiveWall::distance(const double *x, double r, double &dist_minus_r, double *delta) const
{
  delta[0] = delta[1] = delta[2] = 0.0;
  const int a = axis;
  if (shape == Shape::Plane) {
    delta[a] = pos - x[a];
    dist_minus_r = x[a] > pos ? x[a] - pos - r : pos - x[a] - r;
    return true;
  }
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  const double dy = x[b] - c1, dz = x[c] - c2;
  const double dist = std::sqrt(dy * dy + dz * dz);
  if (std::fabs(dist) < 1e-13) return false;  // on the axis: no normal
  if (dist > radius) {
    dist_minus_r = dist - radius - r;
    const double fact = (dist - radius) / dist;
    delta[b] = -dy * fact;
    delta[c] = -dz * fact;
  } else {
    dist_minus_r = radius - dist - r;
    const double fact = (radius - dist) / dist;
    delta[b] = dy * fact;
    delta[c] = dz * fact;
  }
  return true;
}

std::string PrimitiveWall::describe() const
{
  const char ax = "xyz"[axis];
  char buf[160];
  if (shape == Shape::Plane)
    std::snprintf(buf, sizeof buf, "%cplane at %.17g", ax, pos);
  else
    std::snprintf(buf, sizeof buf, "%ccylinder of radius %.17g about (%.17g, %.17g)", ax, radius, c1, c2);
  return buf;
}

void PrimitiveWall::shear_velocity(const double *x, int dim, double v, double *vwall) const
{
  vwall[0] = vwall[1] = vwall[2] = 0.0;
  if (shape == Shape::Plane || dim == axis) {
    vwall[dim] = v;
    return;
  }
  // cylinder spinning about its axis with angular velocity v: ω × (radial vector)
  double w[3] = {0, 0, 0}, rd[3] = {0, 0, 0};
  w[axis] = v;
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  rd[b] = x[b] - c1;
  rd[c] = x[c] - c2;
  vwall[0] = w[1] * rd[2] - w[2] * rd[1];
  vwall[1] = w[2] * rd[0] - w[0] * rd[2];
  vwall[2] = w[0] * rd[1] - w[1] * rd[0];
}

}  // namespace dembridge::walls
