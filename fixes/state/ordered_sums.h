// Contributions of keyed entities (springs, joints, ...) to atoms, summed in key order (LAMMPS-free;
// doc/per_atom_state.md).
//
// A fix evaluating an entity on the owner of one of its atoms adds the result to both atoms, one of which
// may be a ghost. Each atom (local or ghost) collects up to `per_atom` entries [key, width values]; the
// ghost entries travel to their owners by reverse communication, then sum() adds an atom's entries in key
// order, so the total does not depend on which rank evaluated what. Atoms touched by more than
// kMaxOrdered entities (hubs) fall back to one running sum (decomposition-dependent at round-off level).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace dembridge::state {

class OrderedSums {
 public:
  static constexpr int kMaxOrdered = 64;

  // width: values per entry. pairs: (first atom tag, second atom tag or < 0) of every entity. Returns the
  // doubles per atom of one reverse communication (for Fix::comm_reverse).
  int configure(int width, const std::vector<std::pair<long, long>> &pairs);

  int width() const { return width_; }
  bool ordered() const { return ordered_; }

  void reset(int nall);                                        // before an evaluation
  // sign * v to atom i; false if atom i already has every entry configured (internal error).
  bool add(int i, int key, const double *v, double sign);
  int pack(int n, int first, double *buf) const;              // Fix::pack_reverse_comm
  // Fix::unpack_reverse_comm; false if an atom got more entries than configured (internal error).
  bool unpack(int n, const int *list, const double *buf);
  bool empty(int i) const { return count_[i] == 0; }
  void sum(int i, double *out) const;                          // width values, key order

  std::size_t bytes() const { return buf_.capacity() * sizeof(double) + count_.capacity() * sizeof(int); }

 private:
  int width_ = 0, stride_ = 1, per_atom_ = 1;
  bool ordered_ = true;
  std::vector<int> count_;
  std::vector<double> buf_;
  mutable std::vector<int> order_;
  double *entry(int i, int c) { return &buf_[(std::size_t(i) * per_atom_ + c) * stride_]; }
  const double *entry(int i, int c) const { return &buf_[(std::size_t(i) * per_atom_ + c) * stride_]; }
};

}  // namespace dembridge::state
