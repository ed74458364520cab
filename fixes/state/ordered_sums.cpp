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

bool OrderedSums::add_unordered(int i, const double *v, double sign)
{
  double *e = entry(i, 0);
  if (count_[i] == 0) std::fill(e, e + stride_, 0.0);
  count_[i] = 1;
  for (int c = 0; c < width_; c++) e[1 + c] += sign * v[c];
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
  // Insertion sort of the few entries (at most kMaxOrdered) by key, on the stack: keys are distinct, so
  // the order, and hence the rounded sum, is the same as with any other sort.
  const double *sorted[kMaxOrdered];
  for (int c = 0; c < n; c++) {
    const double *x = e + stride_ * c;
    int j = c;
    for (; j > 0 && sorted[j - 1][0] > x[0]; j--) sorted[j] = sorted[j - 1];
    sorted[j] = x;
  }
  std::fill(out, out + width_, 0.0);
  for (int c = 0; c < n; c++)
    for (int m = 0; m < width_; m++) out[m] += sorted[c][1 + m];
}

void OrderedSums::sum_with(int i, const Term *terms, int n, double *out) const
{
  const int ne = count_[i];
  const double *e = entry(i, 0);
  // key, values, sign of every contribution; insertion sort by key (few, distinct keys)
  struct Item {
    double key;
    const double *v;
    double sign;
  };
  Item items[2 * kMaxOrdered];
  int m = 0;
  auto insert = [&](const Item &x) {
    int j = m++;
    for (; j > 0 && items[j - 1].key > x.key; j--) items[j] = items[j - 1];
    items[j] = x;
  };
  for (int c = 0; c < ne; c++) insert({e[stride_ * c], e + stride_ * c + 1, 0.0});
  for (int t = 0; t < n; t++) insert({static_cast<double>(terms[t].key), terms[t].v, terms[t].sign});
  std::fill(out, out + width_, 0.0);
  for (int c = 0; c < m; c++) {
    const Item &x = items[c];
    if (x.sign == 0.0)  // a stored entry: already signed
      for (int w = 0; w < width_; w++) out[w] += x.v[w];
    else
      for (int w = 0; w < width_; w++) out[w] += x.sign * x.v[w];
  }
}

}  // namespace dembridge::state
