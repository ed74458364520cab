#include "spring_table.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dembridge::springs {

SpringTable SpringTable::from_pairs(const std::vector<double>& xy, const char* what) {
  if (xy.size() < 4 || xy.size() % 2 != 0)
    throw std::invalid_argument(std::string(what) + ": expected an even number (>= 4) of values x1 y1 x2 y2 ..., got " +
                                std::to_string(xy.size()));
  SpringTable t;
  for (std::size_t i = 0; i < xy.size(); i += 2) {
    if (!std::isfinite(xy[i]) || !std::isfinite(xy[i + 1]))  // an infinite x would give 0*inf = NaN values
      throw std::invalid_argument(std::string(what) + ": non-finite value at point " + std::to_string(i / 2 + 1));
    if (i > 0 && !(xy[i] > xy[i - 2]))
      throw std::invalid_argument(std::string(what) + ": x values must be strictly increasing (point " +
                                  std::to_string(i / 2 + 1) + ")");
    t.x_.push_back(xy[i]);
    t.y_.push_back(xy[i + 1]);
  }
  t.set_slopes();
  return t;
}

void SpringTable::set_slopes() {
  slope_.clear();
  for (std::size_t i = 0; i + 1 < x_.size(); ++i) slope_.push_back((y_[i + 1] - y_[i]) / (x_[i + 1] - x_[i]));
}

SpringTable SpringTable::zero() {
  SpringTable t;
  // Parmec stores [-REAL_MAX, 0, +REAL_MAX, 0]; (s - x_lo) then overflows for |s| ~ 1e300 and gives 0*inf.
  // Any two x give the same identically zero table, so use finite ones.
  t.x_ = {-1.0, 1.0};
  t.y_ = {0.0, 0.0};
  t.set_slopes();
  return t;
}

SpringTable::Inverse SpringTable::lookup_by_force(double f) const {
  const std::size_t lo = left_interval(y_, f);
  const double dx = x_[lo + 1] - x_[lo];
  const double dy = y_[lo + 1] - y_[lo];
  return {dy / dx, x_[lo] + dx * (f - y_[lo]) / dy};
}

double SpringTable::max_abs_slope() const {
  double m = 0.0;
  for (std::size_t i = 0; i + 1 < x_.size(); ++i)
    m = std::fmax(m, std::fabs((y_[i + 1] - y_[i]) / (x_[i + 1] - x_[i])));
  return m;
}

bool SpringTable::strictly_increasing_values() const {
  for (std::size_t i = 0; i + 1 < y_.size(); ++i)
    if (!(y_[i + 1] > y_[i])) return false;
  return true;
}

}  // namespace dembridge::springs
