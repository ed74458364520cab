#include "park_miller.h"

#include <cmath>
#include <stdexcept>

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

void ParkMiller::restore(const std::array<double, 3> &s)
{
  if (!(s[0] >= 1. && s[0] < double(kM)) || s[0] != double(int(s[0])) || (s[1] != 0. && s[1] != 1.))
    throw std::invalid_argument("the restart file holds no valid random stream state");
  seed_ = int(s[0]);
  have_second_ = s[1] == 1.;
  second_ = s[2];
}

}  // namespace dembridge::insertion
