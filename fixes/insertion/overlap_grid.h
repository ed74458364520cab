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
  int size() const { return static_cast<int>(s_.size()); }

 private:
  // cell index in the padded grid (one empty layer of cells around, so the 27 neighbours of any
  // cell exist); spheres outside [lo, hi] go to the outermost real cells
  int cell_of(const double *x) const;
  struct Sphere {
    double x, y, z, r;
  };
  double lo_[3], inv_[3];
  int n_[3], stride_[3];
  int stencil_[27];  // the candidate's own cell first: an overlap there is the most likely
  std::vector<int> head_, next_;
  std::vector<Sphere> s_;
};

}  // namespace dembridge::insertion
