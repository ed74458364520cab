// Profile (skyline) LU by Crout's method for the joint systems: U has a unit diagonal, the diagonal of L
// is kept inverted, the envelope is symmetric (row k of L and column k of U start at the same index: the
// first nonzero of either). This is the factorisation Parmec's joint solver uses (amgcl skyline_lu on the
// joints' natural order), so the joint reactions round as Parmec's do; and it is O(n b²) for a chain.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

namespace dembridge::rigid {

class SkylineLU {
 public:
  explicit SkylineLU(int n) : n_(n) {}
  void add(int r, int c, double v) { entries_.push_back({r, c, v}); }  // summed in this order onto 0.0
  Eigen::SparseMatrix<double> sparse() const;
  bool factorize();                       // false on a zero pivot
  bool solve(std::vector<double> &b) const;  // in place; false if not factorized

 private:
  double &L(int r, int c) { return low_[start_[r] + (c - lo_[r])]; }
  double &U(int r, int c) { return up_[start_[c] + (r - lo_[c])]; }
  double Lc(int r, int c) const { return low_[start_[r] + (c - lo_[r])]; }
  double Uc(int r, int c) const { return up_[start_[c] + (r - lo_[c])]; }

  int n_;
  struct Entry {
    int r, c;
    double v;
  };
  std::vector<Entry> entries_;
  std::vector<int> lo_, start_;         // envelope start and storage offset of row/column k
  std::vector<double> low_, up_, dinv_;  // L below, U above the diagonal, inverted diagonal
  bool ready_ = false;
};

}  // namespace dembridge::rigid
