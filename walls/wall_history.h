// Per-atom wall contact history (spec liggghts-walls §3, §4.5): up to `capacity` contacts per atom,
// each a key (which wall element: triangle of which mesh; 0 for a primitive wall) and `nvalues`
// history doubles. LAMMPS-free and flat, so that the glue maps grow/copy/exchange/restart onto it
// one to one (and can later hand it to the shared per-atom state layer).
// Row layout per atom: [count, key_0, values_0..., key_1, values_1, ...].
#pragma once

#include <algorithm>
#include <vector>

namespace dembridge::walls {

class WallHistory {
 public:
  void configure(int capacity, int nvalues)
  {
    capacity_ = capacity;
    nvalues_ = nvalues;
    data_.clear();
  }
  int capacity() const { return capacity_; }
  int nvalues() const { return nvalues_; }
  int stride() const { return 1 + capacity_ * (1 + nvalues_); }
  void resize(int nmax) { data_.resize(std::size_t(nmax) * stride(), 0.0); }
  std::size_t bytes() const { return data_.size() * sizeof(double); }

  int count(int i) const { return int(row(i)[0]); }
  double key(int i, int s) const { return row(i)[1 + s * (1 + nvalues_)]; }
  double *values(int i, int s) { return row(i) + 2 + s * (1 + nvalues_); }
  int find(int i, double k) const
  {
    const int n = count(i);
    for (int s = 0; s < n; ++s)
      if (key(i, s) == k) return s;
    return -1;
  }
  // New zeroed slot at the end of atom i's list; -1 when the list is full.
  int add(int i, double k)
  {
    double *r = row(i);
    const int n = int(r[0]);
    if (n >= capacity_) return -1;
    double *slot = r + 1 + n * (1 + nvalues_);
    slot[0] = k;
    std::fill(slot + 1, slot + 1 + nvalues_, 0.0);
    r[0] = n + 1;
    return n;
  }
  // Removes slot s keeping the order of the others.
  void remove(int i, int s)
  {
    double *r = row(i);
    const int n = int(r[0]), w = 1 + nvalues_;
    std::copy(r + 1 + (s + 1) * w, r + 1 + n * w, r + 1 + s * w);
    std::fill(r + 1 + (n - 1) * w, r + 1 + n * w, 0.0);
    r[0] = n - 1;
  }
  void clear(int i) { std::fill(row(i), row(i) + stride(), 0.0); }
  void copy(int from, int to) { std::copy(row(from), row(from) + stride(), row(to)); }
  // Only the used part travels (exchange, restart): returns the number of doubles written/read.
  int packed_size(int i) const { return 1 + count(i) * (1 + nvalues_); }
  int pack(int i, double *buf) const
  {
    const int n = packed_size(i);
    std::copy(row(i), row(i) + n, buf);
    return n;
  }
  int unpack(int i, const double *buf)
  {
    clear(i);
    const int n = 1 + int(buf[0]) * (1 + nvalues_);
    std::copy(buf, buf + n, row(i));
    return n;
  }

 private:
  int capacity_ = 1, nvalues_ = 0;
  std::vector<double> data_;
  double *row(int i) { return data_.data() + std::size_t(i) * stride(); }
  const double *row(int i) const { return data_.data() + std::size_t(i) * stride(); }
};

}  // namespace dembridge::walls
