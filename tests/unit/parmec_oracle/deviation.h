// Worst deviation of a computed series from an oracle series, relative to the series' largest magnitude.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

struct Deviation {
  double max_abs = 0.0;
  double scale = 0.0;
  long worst_row = -1;
  void add(double mine, double ref, long row = -1) {
    const double d = std::fabs(mine - ref);
    if (!(d <= max_abs)) {  // also catches NaN
      max_abs = std::isnan(d) ? INFINITY : d;
      worst_row = row;
    }
    scale = std::max(scale, std::fabs(ref));
  }
  double relative() const { return scale > 0.0 ? max_abs / scale : max_abs; }
  // Printed so that ctest --output-on-failure / the doc can quote the measured agreement.
  void print(const std::string& what) const {
    std::printf("[agreement] %-58s max|diff| %.3e  scale %.3e  relative %.3e (row %ld)\n", what.c_str(), max_abs, scale,
                relative(), worst_row);
  }
};
