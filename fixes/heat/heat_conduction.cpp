#include "heat_conduction.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace dembridge::heat {

namespace {
constexpr double SMALL = 1.0e-5;  // LIGGGHTS's threshold for a zero conductivity or capacity
}

double overlap_contact_area(double r, double ri, double rj)
{
  return -M_PI / 4 * ((r - ri - rj) * (r + ri - rj) * (r - ri + rj) * (r + ri + rj)) / (r * r);
}

double contact_conductance(double ki, double kj, double area)
{
  if (ki < SMALL || kj < SMALL) return 0.0;
  return 4. * ki * kj / (ki + kj) * std::sqrt(area);
}

double updated_temperature(double T, double flux, double source, double dt, double mass, double capacity)
{
  if (!(std::fabs(capacity) > SMALL)) return T;
  return T + (flux + source) * dt / (mass * capacity);
}

double liggghts_initial_temperature(double T0)
{
  char first[512], second[64];
  std::snprintf(first, sizeof first, "%f", T0);
  std::snprintf(second, sizeof second, "%.7g", std::atof(first));
  return std::atof(second);
}

}  // namespace dembridge::heat
