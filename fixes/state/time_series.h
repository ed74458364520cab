// TSERIES: a linear spline of (t, v) points or a constant (spec parmec-springs §3).
#pragma once

#include <vector>

#include "spring_table.h"

namespace dembridge::springs {

class TimeSeries {
 public:
  static TimeSeries constant(double v);
  // [t0, v0, t1, v1, ...] with strictly increasing t; throws std::invalid_argument otherwise.
  static TimeSeries from_pairs(const std::vector<double>& tv);

  // TMS_Value semantics (GRAVITY, DAMPING, PRESCRIBE): constant outside the range.
  double value_clamped(double t) const;
  // Table for a spring `offset` or an UNSPRING `unload` curve: evaluated with SpringTable::lookup,
  // i.e. extrapolated linearly (quirk Q5, replicated as documented). A constant TSERIES has no table
  // in Parmec (undefined behaviour), so this throws for it.
  const SpringTable& as_table(const char* what = "offset") const;

  bool is_constant() const { return table_.empty(); }

 private:
  double constant_ = 0.0;
  SpringTable table_;
};

}  // namespace dembridge::springs
