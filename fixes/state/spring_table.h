// Piecewise-linear lookup table with Parmec's interval and extrapolation rules (spec parmec-springs §3).
#pragma once

#include <cstddef>
#include <cmath>
#include <vector>

namespace dembridge::springs {

class SpringTable {
 public:
  struct Sample {
    double value;
    double slope;
  };
  struct Inverse {
    double slope;  // slope of the interval holding the force
    double at;     // stroke where the (extended) curve takes the force
  };

  SpringTable() = default;

  // Table from [x1, y1, x2, y2, ...]. Throws std::invalid_argument (message says which rule broke)
  // unless it has an even length >= 4 and strictly increasing x (spec §2.1).
  static SpringTable from_pairs(const std::vector<double>& xy, const char* what = "table");
  // The default dashpot/torsion table (Parmec: [-REAL_MAX, 0, +REAL_MAX, 0]): identically zero (spec §3).
  static SpringTable zero();

  // Value and slope at s: the interval x_lo < s <= x_hi (a breakpoint selects its LEFT interval),
  // first/last interval extended linearly outside the table (no clamping). fused: the value rounded
  // once, fma(slope, s - x_lo, y_lo), as Parmec's build forms it (doc/parmec_springs_kernels.md §5, FMA).
  Sample lookup(double s, bool fused = false) const;  // inline below: every spring looks up every step
  // Same search on the y column (curve must be strictly increasing, e.g. an unload curve).
  Inverse lookup_by_force(double f) const;

  double max_abs_slope() const;
  bool strictly_increasing_values() const;
  std::size_t points() const { return x_.size(); }
  const std::vector<double>& x() const { return x_; }
  const std::vector<double>& y() const { return y_; }
  bool empty() const { return x_.empty(); }

 private:
  static std::size_t left_interval(const std::vector<double>& col, double arg);
  void set_slopes();
  std::vector<double> x_, y_;
  // slope_[lo] = (y_[lo+1] - y_[lo]) / (x_[lo+1] - x_[lo]), formed once (the same double as per lookup): a
  // division less in every lookup
  std::vector<double> slope_;
};

// lo with col[lo] < arg <= col[lo+1]; clamped to the first/last interval so that arguments outside the table
// extrapolate linearly (spec §3, §17.9). col is strictly increasing, so lo is the number of inner points
// col[1..n-2] below arg: counted without branches for the short tables of most springs (the binary search's
// lo too, NaN included: 0), else the binary search.
inline std::size_t SpringTable::left_interval(const std::vector<double>& col, double arg) {
  const std::size_t n = col.size();
  if (n <= 8) {
    std::size_t lo = 0;
    for (std::size_t m = 1; m + 1 < n; ++m) lo += arg > col[m];
    return lo;
  }
  std::size_t lo = 0, hi = n;
  while (hi > lo + 1) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (arg > col[mid])
      lo = mid;
    else
      hi = mid;
  }
  if (lo + 1 == col.size()) --lo;
  return lo;
}

[[gnu::always_inline]] inline SpringTable::Sample SpringTable::lookup(double s, bool fused) const {
  const std::size_t lo = left_interval(x_, s);
  const double slope = slope_[lo];
  // value written as y_lo + slope (s - x_lo): round-off decides whether F == 0 exactly (spec §17.9)
  if (fused) return {std::fma(slope, s - x_[lo], y_[lo]), slope};
  return {y_[lo] + slope * (s - x_[lo]), slope};
}

}  // namespace dembridge::springs
