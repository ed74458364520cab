#include "ordered_sums.h"

#include <algorithm>
#include <unordered_map>

namespace dembridge::state {

int OrderedSums::configure(int width, const std::vector<std::pair<long, long>> &pairs)
{
  width_ = width;
  stride_ = 1 + width;
  int kmax = 1, kmax2 = 1;  // most entities on one atom; most with one atom second (only those travel)
  std::unordered_map<long, int> touching, as_second;
  for (const auto &p : pairs) {
    kmax = std::max(kmax, ++touching[p.first]);
    if (p.second >= 0) {
      kmax = std::max(kmax, ++touching[p.second]);
      kmax2 = std::max(kmax2, ++as_second[p.second]);
    }
  }
  ordered_ = kmax <= kMaxOrdered;
  if (!ordered_) kmax = kmax2 = 1;
  per_atom_ = kmax;
  count_.clear();
  buf_.clear();
  return 1 + stride_ * kmax2;
}

void OrderedSums::reset(int nall)
{
  if (static_cast<int>(count_.size()) < nall) {
    count_.resize(nall);
    buf_.resize(std::size_t(nall) * per_atom_ * stride_);
  }
  std::fill(count_.begin(), count_.begin() + nall, 0);
}

bool OrderedSums::add(int i, int key, const double *v, double sign)
{
  if (!ordered_) {
    double *e = entry(i, 0);
    if (count_[i] == 0) std::fill(e, e + stride_, 0.0);
    count_[i] = 1;
    for (int c = 0; c < width_; c++) e[1 + c] += sign * v[c];
    return true;
  }
  if (count_[i] >= per_atom_) return false;
  double *e = entry(i, count_[i]++);
  e[0] = key;
  for (int c = 0; c < width_; c++) e[1 + c] = sign * v[c];
  return true;
}

int OrderedSums::pack(int n, int first, double *buf) const
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    buf[m++] = count_[i];
    const double *e = entry(i, 0);
    for (int c = 0; c < stride_ * count_[i]; c++) buf[m++] = e[c];
  }
  return m;
}

bool OrderedSums::unpack(int n, const int *list, const double *buf)
{
  int m = 0;
  for (int i = 0; i < n; i++) {
    const int j = list[i];
    const int cnt = static_cast<int>(buf[m++]);
    if (!ordered_) {
      if (cnt) {
        double *e = entry(j, 0);
        if (count_[j] == 0) std::fill(e, e + stride_, 0.0);
        count_[j] = 1;
        for (int c = 1; c < stride_; c++) e[c] += buf[m + c];
      }
      m += stride_ * cnt;
      continue;
    }
    if (count_[j] + cnt > per_atom_) return false;
    std::copy(buf + m, buf + m + stride_ * cnt, entry(j, count_[j]));
    count_[j] += cnt;
    m += stride_ * cnt;
  }
  return true;
}

void OrderedSums::sum(int i, double *out) const
{
  const int n = count_[i];
  const double *e = entry(i, 0);
  order_.resize(n);
  for (int c = 0; c < n; c++) order_[c] = c;
  std::sort(order_.begin(), order_.end(), [&](int l, int r) { return e[stride_ * l] < e[stride_ * r]; });
  std::fill(out, out + width_, 0.0);
  for (int c : order_)
    for (int m = 0; m < width_; m++) out[m] += e[stride_ * c + 1 + m];
}

}  // namespace dembridge::state
