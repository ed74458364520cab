#include "pair_force_gather.h"

#include <algorithm>
#include <cstring>

namespace dembridge::threads {

void PairForceGather::build(int inum, const int *ilist, const int *numneigh, int *const *firstneigh, int neighmask, int natoms,
                            int nreceive, int nblocks, const double *row_weight)
{
  natoms_ = std::max(natoms, nreceive);
  nreceive_ = nreceive;
  offset_.assign(std::size_t(inum) + 1, 0);
  list_pos_.assign(std::size_t(natoms_), -1);
  for (int ii = 0; ii < inum; ii++) {
    offset_[ii + 1] = offset_[ii] + std::size_t(numneigh[ilist[ii]]);
    list_pos_[ilist[ii]] = ii;
  }
  // blocks of about equal work (by default: entries, not atoms)
  nblocks = std::max(1, nblocks);
  std::vector<double> work(std::size_t(inum) + 1, 0.0);
  for (int ii = 0; ii < inum; ii++) work[ii + 1] = work[ii] + (row_weight ? row_weight[ii] : double(numneigh[ilist[ii]]));
  block_.assign(std::size_t(nblocks) + 1, inum);
  block_[0] = 0;
  for (int b = 1; b < nblocks; b++)
    block_[b] = int(std::lower_bound(work.begin(), work.end() - 1, work[inum] * b / nblocks) - work.begin());

  // owner block of every atom: the block of its row, else of the first row naming it; an atom
  // named by rows of another block is on the boundary
  std::vector<int> owner(std::size_t(natoms_), -1);
  for (int b = 0; b < nblocks; b++)
    for (int ii = block_[b]; ii < block_[b + 1]; ii++) owner[ilist[ii]] = b;
  boundary_.assign(std::size_t(nreceive), 0);
  for (int b = 0; b < nblocks; b++)
    for (int ii = block_[b]; ii < block_[b + 1]; ii++) {
      const int *jlist = firstneigh[ilist[ii]];
      for (int jj = 0, n = numneigh[ilist[ii]]; jj < n; jj++) {
        const int j = jlist[jj] & neighmask;
        if (j >= nreceive) continue;
        if (owner[j] < 0) owner[j] = b;
        else if (owner[j] != b) boundary_[j] = 1;
      }
    }
  boundary_atoms_.clear();
  std::vector<int> index(std::size_t(nreceive), -1);
  for (int k = 0; k < nreceive; k++)
    if (boundary_[k]) {
      index[k] = int(boundary_atoms_.size());
      boundary_atoms_.push_back(k);
    }
  // counting sort of the boundary atoms' second-atom slots; walking the slots in ascending order
  // keeps each atom's run ascending, i.e. in the serial loop's order
  as_j_start_.assign(boundary_atoms_.size() + 1, 0);
  for (int ii = 0; ii < inum; ii++) {
    const int *jlist = firstneigh[ilist[ii]];
    for (int jj = 0, n = numneigh[ilist[ii]]; jj < n; jj++) {
      const int j = jlist[jj] & neighmask;
      if (j < nreceive && index[j] >= 0) as_j_start_[index[j] + 1]++;
    }
  }
  for (std::size_t k = 0; k < boundary_atoms_.size(); k++) as_j_start_[k + 1] += as_j_start_[k];
  as_j_.resize(as_j_start_.back());
  std::vector<std::size_t> fill(as_j_start_.begin(), as_j_start_.end() - 1);
  for (int ii = 0; ii < inum; ii++) {
    const int *jlist = firstneigh[ilist[ii]];
    for (int jj = 0, n = numneigh[ilist[ii]]; jj < n; jj++) {
      const int j = jlist[jj] & neighmask;
      if (j < nreceive && index[j] >= 0) as_j_[fill[index[j]]++] = offset_[ii] + std::size_t(jj);
    }
  }
  terms_.resize(npairs());
  contact_.assign(npairs(), 0);
}

void PairForceGather::clear_contacts(int ii_from, int ii_to)
{
  if (ii_to > ii_from) std::memset(&contact_[offset_[ii_from]], 0, offset_[ii_to] - offset_[ii_from]);
}

void PairForceGather::gather_boundary(int from, int to, double **f, double **torque) const
{
  for (int b = from; b < to; b++) {
    const int k = boundary_atoms_[b];
    const std::size_t *q = as_j_.data() + as_j_start_[b], *qend = as_j_.data() + as_j_start_[b + 1];
    const int ii = list_pos_[k];
    const std::size_t own_begin = ii >= 0 ? offset_[ii] : 0, own_end = ii >= 0 ? offset_[ii + 1] : 0;
    double fk[3] = {f[k][0], f[k][1], f[k][2]}, tk[3] = {torque[k][0], torque[k][1], torque[k][2]};
    auto add_as_j = [&](std::size_t p) {
      if (!contact_[p]) return;
      const PairTerms &t = terms_[p];
      for (int c = 0; c < 3; c++) {
        fk[c] -= t.F[c];
        tk[c] += t.Tj[c];
      }
    };
    // the serial loop reaches atom k's pairs in slot order: those of earlier rows (k as j), then
    // k's own row, then those of later rows
    for (; q != qend && *q < own_begin; ++q) add_as_j(*q);
    for (std::size_t p = own_begin; p < own_end; p++) {
      if (!contact_[p]) continue;
      const PairTerms &t = terms_[p];
      for (int c = 0; c < 3; c++) {
        fk[c] += t.F[c];
        tk[c] += t.Ti[c];
      }
    }
    for (; q != qend; ++q) add_as_j(*q);
    for (int c = 0; c < 3; c++) {
      f[k][c] = fk[c];
      torque[k][c] = tk[c];
    }
  }
}

std::size_t PairForceGather::memory_bytes() const
{
  return block_.capacity() * sizeof(int) + offset_.capacity() * sizeof(std::size_t) + list_pos_.capacity() * sizeof(int) +
         boundary_.capacity() + boundary_atoms_.capacity() * sizeof(int) + as_j_start_.capacity() * sizeof(std::size_t) +
         as_j_.capacity() * sizeof(std::size_t) + terms_.capacity() * sizeof(PairTerms) + contact_.capacity();
}

}  // namespace dembridge::threads
