// Threaded accumulation of pair forces that gives the serial loop's result bit for bit, for any
// thread count. The serial loop adds each contact's force and torques to atom i and atom j as it
// walks a half neighbour list; two threads doing that would race on shared atoms, and per-thread
// force copies summed afterwards change the order of the additions (round-off, then chaos in a
// dense granular bed).
//
// Here the list is cut into contiguous blocks of rows, one per thread. An atom all of whose pairs
// lie in one block ("interior") is written only by that block's thread, in row order: the serial
// order. An atom with pairs in two blocks ("boundary": a thin layer where blocks meet) is not
// written during the pass; its pairs' terms are kept in one slot per list entry, and a second pass
// adds them to the atom in slot order, which is again the serial order. Each addition happens in
// exactly the serial sequence, so the sums are identical to one thread's.
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
  // Index a half neighbour list once per rebuild, cut into nblocks blocks of about equal work:
  // row_weight[ii] (the expected cost of row ii), or the number of entries when null. Atoms with
  // index < nreceive receive their share as the second atom of a pair (nlocal with newton off,
  // nlocal + nghost with newton on); entries are masked with neighmask. natoms bounds every atom
  // index in the list.
  void build(int inum, const int *ilist, const int *numneigh, int *const *firstneigh, int neighmask, int natoms,
             int nreceive, int nblocks, const double *row_weight = nullptr);

  int inum() const { return offset_.empty() ? -1 : int(offset_.size()) - 1; }
  int natoms() const { return natoms_; }
  int nreceive() const { return nreceive_; }
  int nblocks() const { return int(block_.size()) - 1; }
  std::size_t npairs() const { return offset_.empty() ? 0 : offset_.back(); }
  // List rows [block_begin(b), block_begin(b + 1)) form block b.
  int block_begin(int b) const { return block_[b]; }
  // Slot of the first neighbour of the ii-th list atom; the jj-th neighbour is first_pair(ii) + jj.
  std::size_t first_pair(int ii) const { return offset_[ii]; }
  int nboundary() const { return int(boundary_atoms_.size()); }

  // Pass 1, one thread per block, rows in order: clear the block's contact flags, then add each
  // contact. It goes straight to interior atoms; its terms are kept when an atom is on the
  // boundary, or always with keep_all (for a later walk over every contact, e.g. the virial).
  void clear_contacts(int ii_from, int ii_to);
  void add(std::size_t p, int i, int j, const double F[3], const double Ti[3], const double Tj[3], double **f, double **torque,
           bool keep_all)
  {
    const bool j_receives = j < nreceive_;
    const bool bi = boundary_[i] != 0, bj = j_receives && boundary_[j] != 0;
    if (!bi)
      for (int c = 0; c < 3; c++) {
        f[i][c] += F[c];
        torque[i][c] += Ti[c];
      }
    if (j_receives && !bj)
      for (int c = 0; c < 3; c++) {
        f[j][c] -= F[c];
        torque[j][c] += Tj[c];
      }
    if (bi || bj || keep_all) {
      PairTerms &t = terms_[p];
      for (int c = 0; c < 3; c++) {
        t.F[c] = F[c];
        t.Ti[c] = Ti[c];
        t.Tj[c] = Tj[c];
      }
      contact_[p] = 1;
    }
  }
  bool kept(std::size_t p) const { return contact_[p] != 0; }
  const PairTerms &terms(std::size_t p) const { return terms_[p]; }

  // Pass 2 (any thread, disjoint ranges of [0, nboundary())): the boundary atoms' sums, in slot order.
  void gather_boundary(int from, int to, double **f, double **torque) const;

  std::size_t memory_bytes() const;

 private:
  int natoms_ = 0, nreceive_ = 0;
  std::vector<int> block_;               // first row of each block; block_[nblocks] = inum
  std::vector<std::size_t> offset_;      // per list row ii: first slot; offset_[inum] = npairs
  std::vector<int> list_pos_;            // per atom: its row in the list, -1 if it has none
  std::vector<unsigned char> boundary_;  // per receiving atom: has pairs in two blocks
  std::vector<int> boundary_atoms_;
  std::vector<std::size_t> as_j_start_;  // per boundary atom (by its index in boundary_atoms_): its run in as_j_
  std::vector<std::size_t> as_j_;        // slots where the boundary atom is the second atom, ascending
  std::vector<PairTerms> terms_;
  std::vector<unsigned char> contact_;
};

}  // namespace dembridge::threads
