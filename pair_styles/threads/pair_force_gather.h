// Threaded accumulation of pair forces that gives the serial loop's result bit for bit, for any
// thread count. The serial loop adds each contact's force and torques to atom i and atom j as it
// walks a half neighbour list; two threads doing that would race on shared atoms, and per-thread
// force copies summed afterwards change the order of the additions (round-off, then chaos in a
// dense granular bed). Here the contacts are evaluated in parallel into one slot per list entry
// (pass 1), and every atom then sums the slots of its own pairs in list order (pass 2): each
// atom's additions happen in exactly the serial order, and each atom is written by one thread.
// LAMMPS-free: the neighbour list comes in as LAMMPS's arrays (ilist, numneigh, firstneigh).
#pragma once

#include <cstddef>
#include <vector>

namespace dembridge::threads {

// What one contact gives its two atoms: +F and Ti to i, -F and Tj to j.
struct PairTerms {
  double F[3], Ti[3], Tj[3];
};

class PairForceGather {
 public:
  // Index a half neighbour list once per rebuild. Atoms with index < nreceive receive their share
  // as the second atom of a pair (nlocal with newton off, nlocal + nghost with newton on); neighbour
  // entries are masked with neighmask. natoms bounds every atom index in the list.
  void build(int inum, const int *ilist, const int *numneigh, int *const *firstneigh, int neighmask, int natoms,
             int nreceive);

  std::size_t npairs() const { return offset_.empty() ? 0 : offset_.back(); }
  int nreceive() const { return nreceive_; }
  int inum() const { return offset_.empty() ? -1 : int(offset_.size()) - 1; }
  int natoms() const { return int(list_pos_.size()); }
  // Slot of the first neighbour of the ii-th list atom; the jj-th neighbour is first_pair(ii) + jj.
  std::size_t first_pair(int ii) const { return offset_[ii]; }

  // Pass 1 (any thread, disjoint ii ranges): clear the contact flags of list atoms [ii_from, ii_to),
  // then store each contact.
  void clear_contacts(int ii_from, int ii_to);
  void store(std::size_t p, const double F[3], const double Ti[3], const double Tj[3])
  {
    PairTerms &t = terms_[p];
    for (int k = 0; k < 3; k++) {
      t.F[k] = F[k];
      t.Ti[k] = Ti[k];
      t.Tj[k] = Tj[k];
    }
    contact_[p] = 1;
  }
  bool in_contact(std::size_t p) const { return contact_[p] != 0; }
  const PairTerms &terms(std::size_t p) const { return terms_[p]; }

  // Pass 2 (any thread, disjoint atom ranges within [0, nreceive)): f[k] and torque[k] += the
  // stored terms of atom k's pairs, in list order.
  void gather(int k_from, int k_to, double **f, double **torque) const;

  std::size_t memory_bytes() const;

 private:
  int nreceive_ = 0;
  std::vector<std::size_t> offset_;    // per list atom ii: first slot; offset_[inum] = npairs
  std::vector<int> list_pos_;          // per atom: its ii in the list, -1 if it has no list row
  std::vector<std::size_t> as_j_start_;  // per receiving atom: its run in as_j_ (CSR)
  std::vector<std::size_t> as_j_;      // slots where the atom is the second atom, ascending
  std::vector<PairTerms> terms_;
  std::vector<unsigned char> contact_;
};

}  // namespace dembridge::threads
