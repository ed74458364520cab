#include "skyline_lu.h"

#include <algorithm>

namespace dembridge::rigid {

Eigen::SparseMatrix<double> SkylineLU::sparse() const
{
  std::vector<Eigen::Triplet<double>> t;
  for (const Entry &e : entries_) t.emplace_back(e.r, e.c, e.v);
  Eigen::SparseMatrix<double> A(n_, n_);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

bool SkylineLU::factorize()
{
  // envelope from the nonzero values (zeros are not stored, as in amgcl; an entry is judged by each of its
  // contributions, which differs only for contributions cancelling exactly)
  lo_.resize(n_);
  for (int k = 0; k < n_; k++) lo_[k] = k;
  for (const Entry &e : entries_) {
    if (e.v == 0.0 || e.r == e.c) continue;
    if (e.r > e.c) lo_[e.r] = std::min(lo_[e.r], e.c);
    else lo_[e.c] = std::min(lo_[e.c], e.r);
  }
  start_.assign(n_ + 1, 0);
  for (int k = 0; k < n_; k++) start_[k + 1] = start_[k] + (k - lo_[k]);
  low_.assign(start_[n_], 0.0);
  up_.assign(start_[n_], 0.0);
  dinv_.assign(n_, 0.0);
  for (const Entry &e : entries_) {
    if (e.v == 0.0) continue;
    if (e.r > e.c) L(e.r, e.c) += e.v;
    else if (e.r < e.c) U(e.r, e.c) += e.v;
    else dinv_[e.r] += e.v;
  }
  if (dinv_[0] == 0.0) return ready_ = false;
  dinv_[0] = 1.0 / dinv_[0];
  for (int k = 1; k < n_; k++) {
    const int b = lo_[k];
    if (b == 0) U(0, k) = dinv_[0] * U(0, k);
    for (int i = std::max(b, 1); i < k; i++) {  // column k of U
      double sum = U(i, k);
      for (int j = std::max(b, lo_[i]); j < i; j++) sum -= L(i, j) * U(j, k);
      U(i, k) = dinv_[i] * sum;
    }
    for (int i = std::max(b, 1); i < k; i++) {  // row k of L
      double sum = L(k, i);
      for (int j = std::max(b, lo_[i]); j < i; j++) sum -= L(k, j) * U(j, i);
      L(k, i) = sum;
    }
    double sum = dinv_[k];  // the diagonal entry, still uninverted
    for (int j = b; j < k; j++) sum -= L(k, j) * U(j, k);
    if (sum == 0.0) return ready_ = false;
    dinv_[k] = 1.0 / sum;
  }
  return ready_ = true;
}

bool SkylineLU::solve(std::vector<double> &y) const
{
  if (!ready_ || int(y.size()) != n_) return false;
  for (int i = 0; i < n_; i++) {
    double sum = y[i];
    for (int j = lo_[i]; j < i; j++) sum -= Lc(i, j) * y[j];
    y[i] = dinv_[i] * sum;
  }
  for (int j = n_ - 1; j >= 0; j--)
    for (int i = lo_[j]; i < j; i++) y[i] -= Uc(i, j) * y[j];
  return true;
}

}  // namespace dembridge::rigid
