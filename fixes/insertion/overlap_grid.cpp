#include "overlap_grid.h"

#include <algorithm>
#include <cmath>

namespace dembridge::insertion {

OverlapGrid::OverlapGrid(const double *lo, const double *hi, double cell)
{
  // at most ~4 M cells: a coarser grid stays exact (the cell only grows)
  double edge = cell > 0.0 ? cell : 1.0;
  for (;;) {
    double ncell = 1.0;
    for (int d = 0; d < 3; ++d) ncell *= std::max(1.0, std::floor((hi[d] - lo[d]) / edge));
    if (ncell <= 4.0e6) break;
    edge *= 1.5;
  }
  for (int d = 0; d < 3; ++d) {
    lo_[d] = lo[d];
    n_[d] = std::max(1, static_cast<int>(std::floor((hi[d] - lo[d]) / edge)));
    inv_[d] = n_[d] / std::max(hi[d] - lo[d], 1e-300);
  }
  head_.assign(static_cast<size_t>(n_[0]) * n_[1] * n_[2], -1);
}

int OverlapGrid::cell_of(const double *x, int *c) const
{
  for (int d = 0; d < 3; ++d) {
    const double t = (x[d] - lo_[d]) * inv_[d];
    c[d] = t < 0.0 ? 0 : (t >= n_[d] ? n_[d] - 1 : static_cast<int>(t));
  }
  return (c[2] * n_[1] + c[1]) * n_[0] + c[0];
}

void OverlapGrid::add(const double *x, double r)
{
  int c[3];
  const int cell = cell_of(x, c);
  const int id = static_cast<int>(r_.size());
  x_.insert(x_.end(), x, x + 3);
  r_.push_back(r);
  next_.push_back(head_[cell]);
  head_[cell] = id;
}

bool OverlapGrid::overlaps(const double *x, double r) const
{
  int c[3];
  cell_of(x, c);
  for (int k = std::max(0, c[2] - 1); k <= std::min(n_[2] - 1, c[2] + 1); ++k)
    for (int j = std::max(0, c[1] - 1); j <= std::min(n_[1] - 1, c[1] + 1); ++j)
      for (int i = std::max(0, c[0] - 1); i <= std::min(n_[0] - 1, c[0] + 1); ++i)
        for (int p = head_[(k * n_[1] + j) * n_[0] + i]; p >= 0; p = next_[p]) {
          const double *q = &x_[3 * p];
          const double dx = x[0] - q[0], dy = x[1] - q[1], dz = x[2] - q[2];
          const double rsq = dx * dx + dy * dy + dz * dz;
          const double radsum = r + r_[p];
          if (rsq <= radsum * radsum) return true;
        }
  return false;
}

}  // namespace dembridge::insertion
