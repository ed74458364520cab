#include "time_series.h"

#include <stdexcept>
#include <string>

namespace dembridge::springs {

TimeSeries TimeSeries::constant(double v) {
  TimeSeries s;
  s.constant_ = v;
  return s;
}

TimeSeries TimeSeries::from_pairs(const std::vector<double>& tv) {
  TimeSeries s;
  s.table_ = SpringTable::from_pairs(tv, "TSERIES");
  return s;
}

double TimeSeries::value_clamped(double t) const {
  if (table_.empty()) return constant_;
  const auto& x = table_.x();
  if (t <= x.front()) return table_.y().front();
  if (t >= x.back()) return table_.y().back();
  return table_.lookup(t).value;
}

const SpringTable& TimeSeries::as_table(const char* what) const {
  if (table_.empty())
    throw std::invalid_argument(std::string(what) + ": a constant TSERIES cannot be used here; give at least two (t, v) points");
  return table_;
}

}  // namespace dembridge::springs
