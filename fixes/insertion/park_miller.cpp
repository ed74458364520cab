#include "park_miller.h"

#include <cmath>

namespace dembridge::insertion {

double ParkMiller::gaussian()
{
  if (have_second_) {
    have_second_ = false;
    return second_;
  }
  double v1, v2, rsq;
  do {
    v1 = 2.0 * uniform() - 1.0;
    v2 = 2.0 * uniform() - 1.0;
    rsq = v1 * v1 + v2 * v2;
  } while (!(rsq < 1.0 && rsq != 0.0));
  const double fac = std::sqrt(-2.0 * std::log(rsq) / rsq);
  second_ = v1 * fac;
  have_second_ = true;
  return v2 * fac;
}

}  // namespace dembridge::insertion
