// Per-atom lists of fixed-size state records (LAMMPS-free; doc/per_atom_state.md).
//
// Each atom holds any number of records of `record_size` doubles; element 0 of a record is its key (the
// definition index of the spring, joint or restraint, the partner of a contact, the wall element of a
// wall contact). The lists move with
// their atom: copy (sort, deletion), pack/unpack (exchange, restart). The layer never reads beyond the
// key, so any fix with per-atom, per-entity state can keep it here.
#pragma once

#include "atom_lists.h"

#include <cstddef>
#include <utility>
#include <vector>

namespace dembridge::state {

class RecordLists final : public AtomLists {
 public:
  explicit RecordLists(int record_size) : rs_(record_size) {}

  int record_size() const { return rs_; }
  void resize(int nmax) override { lists_.resize(nmax); }
  int count(int i) const { return static_cast<int>(lists_[i].size()) / rs_; }
  double *record(int i, int r) { return &lists_[i][std::size_t(r) * rs_]; }
  const double *record(int i, int r) const { return &lists_[i][std::size_t(r) * rs_]; }
  int key(int i, int r) const { return static_cast<int>(lists_[i][std::size_t(r) * rs_]); }

  // A zeroed record with this key appended to atom i (pointer valid until atom i's list changes).
  // Keys are whole numbers held exactly in a double (wall contacts use keys beyond int).
  double *append(int i, double key);
  // The first record of atom i with this key, or -1.
  int find(int i, double key) const;
  void erase(int i, int r);   // the last record takes its place (order is not kept)
  void remove(int i, int r);  // the later records move up one place (order kept)
  void clear(int i) override;  // also frees the atom's memory
  void copy(int from, int to) override;

  // Wire format of one atom: [n, n values]; pack returns the doubles written, unpack those read.
  int packed_size(int i) const override { return 1 + static_cast<int>(lists_[i].size()); }
  int pack(int i, double *buf) const override;
  int unpack(int i, const double *buf) override;
  // n whole records, and nothing else.
  bool is_packed_atom(const double *buf, int size) const override;

  // Sum of count(i) over atoms 0..n-1.
  long total(int n) const;
  // Bytes held by atoms 0..n-1 (records and each list's allocation header) and by the list objects.
  double bytes(int n) const;
  static constexpr double kChunkHeader = 16;  // what malloc adds to each block, on average

  // Incremented whenever records move between atoms or appear/disappear: index caches compare it.
  unsigned long generation() const { return generation_; }

 private:
  int rs_;
  std::vector<std::vector<double>> lists_;
  unsigned long generation_ = 0;
};

// key -> (atom, record) of the records held by atoms 0..n-1, rebuilt only when the lists changed.
class RecordIndex {
 public:
  // (-1, -1) when no local atom holds a record of this key (keys must lie in 0..nkeys-1).
  std::pair<int, int> find(const RecordLists &lists, int n, int nkeys, int key);
  double bytes() const { return double(where_.capacity()) * sizeof(where_[0]); }

 private:
  std::vector<std::pair<int, int>> where_;
  unsigned long generation_ = ~0ul;
  int n_ = -1;
};

}  // namespace dembridge::state
