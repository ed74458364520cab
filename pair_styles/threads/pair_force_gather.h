// Threaded accumulation of pair forces that gives the serial loop's result bit for bit, for any
// thread count. The serial loop adds each contact's force and torques to atom i and atom j as it
// walks a half neighbour list; two threads doing that would race on shared atoms, and per-thread
// force copies summed afterwards change the order of the additions (round-off, then chaos in a
// dense granular bed).
//
// Here the list is cut into contiguous blocks of rows, one per thread. Every atom named by a
// block's rows (its own row or as a neighbour) has a first block: the lowest-numbered block naming
// it. In the serial order all of that block's additions to the atom come before those of any later
// block, so the first block's thread adds straight to the atom, in row order. A later block's thread
// must not touch the atom yet: it appends the term to its block's log (in row order). After every
// block is done, the logs are applied block after block, each in its own order, atom by atom: again
// exactly the serial sequence of additions, so the sums are identical to one thread's. Atoms named by
// one block only (nearly all, the list being sorted in space) never reach a log.
// LAMMPS-free: the neighbour list comes in as LAMMPS's arrays (ilist, numneigh, firstneigh); per-atom
// vectors are flat (f[3*k + c]).
#pragma once

#include "math/vec3.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dembridge::threads {

class PairForceGather {
 public:
  // Index a half neighbour list once per rebuild, in three phases so that threads can share the
  // work (build() runs them all on the calling thread):
  //  1. index (one thread): rows' first slots and nblocks blocks of about equal work: row_weight[ii]
  //     (the expected cost of row ii), or the number of entries when null. Atoms with index <
  //     nreceive receive their share as the second atom of a pair (nlocal with newton off, nlocal +
  //     nghost with newton on); every list atom ilist[ii] is below nreceive.
  //  2. mark_block(b) for every block (any thread, any order): the atoms block b names.
  //  3. resolve(from, to) on disjoint ranges covering [0, nreceive) (any thread): first blocks.
  void index(int inum, const int *ilist, const int *numneigh, int nreceive, int nblocks, const double *row_weight = nullptr);
  void mark_block(int b, const int *ilist, const int *numneigh, int *const *firstneigh, int neighmask);
  void resolve(int from, int to);
  void build(int inum, const int *ilist, const int *numneigh, int *const *firstneigh, int neighmask, int nreceive, int nblocks,
             const double *row_weight = nullptr);

  int inum() const { return offset_.empty() ? -1 : int(offset_.size()) - 1; }
  int nreceive() const { return nreceive_; }
  int nblocks() const { return int(block_.size()) - 1; }
  std::size_t npairs() const { return offset_.empty() ? 0 : offset_.back(); }
  // List rows [block_begin(b), block_begin(b + 1)) form block b.
  int block_begin(int b) const { return block_[b]; }
  // Slot of the first neighbour of the ii-th list atom; the jj-th neighbour is first_pair(ii) + jj.
  std::size_t first_pair(int ii) const { return offset_[ii]; }
  // Atoms whose terms block b defers to its log (named by an earlier block); diagnostics and tests.
  int ndeferred_atoms(int b) const;

  // Pass 1, one thread per block, its rows in order: begin_block(b), then add() for each contact
  // (slot = first_pair(ii) + jj). With keep_all every contact's F is also kept for a later walk
  // over all contacts (the virial), and begin_block clears the block's flags of the last such step.
  void begin_block(int b, bool keep_all);
  void add(int b, int i, int j, const double F[3], const double Ti[3], const double Tj[3], double *f, double *torque)
  {
    if (first_block_[i] == b) {
      math::add_into(f + 3 * std::ptrdiff_t(i), F);
      math::add_into(torque + 3 * std::ptrdiff_t(i), Ti);
    } else
      defer(b, i, F, Ti, 1.0);
    if (j >= nreceive_) return;
    if (first_block_[j] == b) {
      math::subtract_from(f + 3 * std::ptrdiff_t(j), F);
      math::add_into(torque + 3 * std::ptrdiff_t(j), Tj);
    } else
      defer(b, j, F, Tj, -1.0);  // f - F and f + (-F) are the same number
  }
  void keep(std::size_t slot, const double F[3])
  {
    for (int c = 0; c < 3; c++) kept_F_[3 * slot + c] = F[c];
    kept_[slot] = 1;
  }
  bool kept(std::size_t slot) const { return kept_[slot] != 0; }
  const double *kept_force(std::size_t slot) const { return &kept_F_[3 * slot]; }

  // Pass 2, after every block's pass 1: the logs' terms of the atoms k with k % nparts == part
  // (one call per part, any thread), blocks in order, each log in its order.
  void apply_deferred(int part, int nparts, double *f, double *torque) const;

  std::size_t memory_bytes() const;

 private:
  struct Deferred {
    int k;
    double F[3], T[3];
  };
  struct alignas(64) Log {  // one per block, written by its thread only (own cache lines)
    std::vector<Deferred> terms;
  };

  int nreceive_ = 0;
  std::vector<int> block_;             // first row of each block; block_[nblocks] = inum
  std::vector<std::size_t> offset_;    // per list row ii: first slot; offset_[inum] = npairs
  std::vector<unsigned char> named_;   // [b * nreceive + k]: block b names atom k (rebuild scratch)
  std::vector<std::uint16_t> first_block_;  // per receiving atom: the first block naming it
  std::vector<Log> log_;
  std::vector<double> kept_F_;         // per slot, steps with keep_all
  std::vector<unsigned char> kept_;

  void defer(int b, int k, const double F[3], const double T[3], double sign)
  {
    log_[b].terms.push_back({k, {sign * F[0], sign * F[1], sign * F[2]}, {T[0], T[1], T[2]}});
  }
};

}  // namespace dembridge::threads
