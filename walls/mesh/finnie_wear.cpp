#include "finnie_wear.h"

#include <cmath>

namespace dembridge::mesh {

namespace {
constexpr double EPSILON = 0.001;  // LIGGGHTS's grazing limit of cos(gamma)
}

double finnie_angle_factor(double sin_gamma, double cos_gamma)
{
  if (cos_gamma < EPSILON || 3. * sin_gamma > cos_gamma) return 0.33333 * cos_gamma * cos_gamma;
  const double sin_2gamma = 2. * sin_gamma * cos_gamma;
  return sin_2gamma - 3. * sin_gamma * sin_gamma;
}

double finnie_wear_increment(const Vec3 &c, const Vec3 &v_rel, const Vec3 &normal, double k_finnie,
                             double force_magnitude, double dt, double area)
{
  if (dot(c, v_rel) < 0.) return 0.0;
  const double v_rel_mag = norm(v_rel);
  if (0.0000001 > v_rel_mag) return 0.0;
  double sin_gamma = std::fabs(dot(v_rel, normal)) / v_rel_mag;
  double cos_gamma = std::fabs(norm(cross(v_rel, normal))) / v_rel_mag;
  if (cos_gamma > 1.) cos_gamma = 1.;
  if (sin_gamma > 1.) sin_gamma = 1.;
  double E = finnie_angle_factor(sin_gamma, cos_gamma);
  E *= 2. * k_finnie * v_rel_mag * force_magnitude;
  return E * dt / area;
}

}  // namespace dembridge::mesh
