#include "timestep_estimates.h"

#include <algorithm>
#include <cmath>

namespace dembridge::gran {

double rayleigh_time(double r, double rho, double Y, double nu)
{
  const double shear_mod = Y / (2. * (nu + 1.));
  return M_PI * r * std::sqrt(rho / shear_mod) / (0.1631 * nu + 0.8766);
}

double effective_modulus(double Yi, double nui, double Yj, double nuj)
{
  return 1. / ((1. - std::pow(nui, 2.)) / Yi + (1. - std::pow(nuj, 2.)) / Yj);
}

double hertz_time(double r, double rho, double Yeff, double v_rel)
{
  const double meff = 4. * r * r * r * M_PI / 3. * rho;
  const double reff = r / 2.;
  return 2.87 * std::pow(meff * meff / (reff * Yeff * Yeff * v_rel), 0.2);
}

double relative_speed(double vmax_particle, double vmax_mesh)
{
  return std::max(2. * vmax_particle, vmax_particle + vmax_mesh);
}

double sphere_density(double mass, double r) { return mass / (4. * M_PI / 3. * r * r * r); }

}  // namespace dembridge::gran
