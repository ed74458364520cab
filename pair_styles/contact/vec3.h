// Minimal 3-vector helpers on plain double[3] (LAMMPS arrays are double**; no copies needed).
#pragma once

#include <cmath>

namespace dembridge::gran {

inline double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline void cross3(const double *a, const double *b, double *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
inline double len3(const double *a) { return std::sqrt(dot3(a, a)); }

constexpr double kPi = 3.14159265358979323846;

}  // namespace dembridge::gran
