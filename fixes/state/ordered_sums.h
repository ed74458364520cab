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
  // sign * v to atom i; false if atom i already has every entry configured (internal error). Inline: it
  // runs twice per entity and step.
  bool add(int i, int key, const double *v, double sign)
  {
    if (!ordered_) return add_unordered(i, v, sign);
    if (count_[i] >= per_atom_) return false;
    double *e = entry(i, count_[i]++);
    e[0] = key;
    for (int c = 0; c < width_; c++) e[1 + c] = sign * v[c];
    return true;
  }
  int pack(int n, int first, double *buf) const;              // Fix::pack_reverse_comm
  // Fix::unpack_reverse_comm; false if an atom got more entries than configured (internal error).
  bool unpack(int n, const int *list, const double *buf);
  bool empty(int i) const { return count_[i] == 0; }
  // Ordered mode: atom i's entries, each [key, width values with their sign] (for fixes that combine
  // them in an order of their own, e.g. Parmec's per-body runs in fix parmec/spring 'order parmec').
  int count(int i) const { return count_[i]; }
  const double *entry_of(int i, int c) const { return entry(i, c); }
  // width values, key order. Thread-safe for distinct atoms (no shared scratch).
  void sum(int i, double *out) const;
  // Atom i's entries merged with n further terms (sign * v, as add() would store them) of keys that
  // are not among its entries, all summed in key order: equal to add()ing the terms, then sum().
  struct Term {
    int key;
    const double *v;
    double sign;
  };
  void sum_with(int i, const Term *terms, int n, double *out) const;

  std::size_t bytes() const { return buf_.capacity() * sizeof(double) + count_.capacity() * sizeof(int); }

 private:
  int width_ = 0, stride_ = 1, per_atom_ = 1;
  bool ordered_ = true;
  std::vector<int> count_;
  std::vector<double> buf_;
  bool add_unordered(int i, const double *v, double sign);
  double *entry(int i, int c) { return &buf_[(std::size_t(i) * per_atom_ + c) * stride_]; }
  const double *entry(int i, int c) const { return &buf_[(std::size_t(i) * per_atom_ + c) * stride_]; }
};

}  // namespace dembridge::state
