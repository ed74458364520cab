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
  stride_[0] = 1;
  stride_[1] = n_[0] + 2;
  stride_[2] = (n_[0] + 2) * (n_[1] + 2);
  int k = 0;
  stencil_[k++] = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (dx || dy || dz) stencil_[k++] = dz * stride_[2] + dy * stride_[1] + dx;
  head_.assign(static_cast<size_t>(n_[0] + 2) * (n_[1] + 2) * (n_[2] + 2), -1);
}

int OverlapGrid::cell_of(const double *x) const
{
  int cell = 0;
  for (int d = 0; d < 3; ++d) {
    const double t = (x[d] - lo_[d]) * inv_[d];
    const int c = t < 0.0 ? 0 : (t >= n_[d] ? n_[d] - 1 : static_cast<int>(t));
    cell += (c + 1) * stride_[d];
  }
  return cell;
}

void OverlapGrid::add(const double *x, double r)
{
  const int cell = cell_of(x);
  s_.push_back({x[0], x[1], x[2], r});
  next_.push_back(head_[cell]);
  head_[cell] = static_cast<int>(s_.size()) - 1;
}

bool OverlapGrid::overlaps(const double *x, double r) const
{
  const int cell = cell_of(x);
  for (int k = 0; k < 27; ++k)
    for (int p = head_[cell + stencil_[k]]; p >= 0; p = next_[p]) {
      const Sphere &q = s_[p];
      const double dx = x[0] - q.x, dy = x[1] - q.y, dz = x[2] - q.z;
      const double rsq = dx * dx + dy * dy + dz * dz;
      const double radsum = r + q.r;
      if (rsq <= radsum * radsum) return true;
    }
  return false;
}

}  // namespace dembridge::insertion
