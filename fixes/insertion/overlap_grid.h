// Spheres binned in cubic cells for the insertion overlap test. The test is exact (every sphere that
// can touch is looked at) when the cell edge is at least the largest sum of two radii, and it uses
// LIGGGHTS's comparison: touching (|d|^2 <= (r1+r2)^2) counts as an overlap. LAMMPS-free.
#pragma once

#include <vector>

namespace dembridge::insertion {

class OverlapGrid {
 public:
  // Cells cover [lo, hi] (spheres outside are kept in the edge cells); cell >= largest r1 + r2.
  OverlapGrid(const double *lo, const double *hi, double cell);
  void add(const double *x, double r);
  bool overlaps(const double *x, double r) const;
  int size() const { return static_cast<int>(r_.size()); }

 private:
  int cell_of(const double *x, int *c) const;
  double lo_[3], inv_[3];
  int n_[3];
  std::vector<int> head_, next_;
  std::vector<double> x_, r_;
};

}  // namespace dembridge::insertion
