// Minimal 3-vector helpers on plain double[3] (LAMMPS arrays are double**; no copies needed).
#pragma once

#include "lane_math.h"

#include <cmath>

namespace dembridge::gran {

// R: double, or Lanes4 (lane_math.h)
template <class R> [[gnu::always_inline]] inline R dot3(const R *a, const R *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
template <class R> [[gnu::always_inline]] inline void cross3(const R *a, const R *b, R *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
template <class R> [[gnu::always_inline]] inline R len3(const R *a) { return lane_sqrt(dot3(a, a)); }

constexpr double kPi = 3.14159265358979323846;

}  // namespace dembridge::gran
