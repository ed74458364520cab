#include "pair_force_gather.h"

#include <algorithm>
#include <cstring>

namespace dembridge::threads {

void PairForceGather::build(int inum, const int *ilist, const int *numneigh, int *const *firstneigh, int neighmask,
                            int natoms, int nreceive)
{
  nreceive_ = nreceive;
  offset_.assign(std::size_t(inum) + 1, 0);
  list_pos_.assign(std::size_t(std::max(natoms, nreceive)), -1);
  for (int ii = 0; ii < inum; ii++) {
    offset_[ii + 1] = offset_[ii] + std::size_t(numneigh[ilist[ii]]);
    list_pos_[ilist[ii]] = ii;
  }
  // counting sort of the slots by their second atom; walking the slots in ascending order keeps
  // each atom's run ascending, i.e. in the serial loop's order
  as_j_start_.assign(std::size_t(nreceive) + 1, 0);
  for (int ii = 0; ii < inum; ii++) {
    const int *jlist = firstneigh[ilist[ii]];
    for (int jj = 0, n = numneigh[ilist[ii]]; jj < n; jj++) {
      const int j = jlist[jj] & neighmask;
      if (j < nreceive) as_j_start_[j + 1]++;
    }
  }
  for (int k = 0; k < nreceive; k++) as_j_start_[k + 1] += as_j_start_[k];
  as_j_.resize(as_j_start_[nreceive]);
  std::vector<std::size_t> fill(as_j_start_.begin(), as_j_start_.end() - 1);
  for (int ii = 0; ii < inum; ii++) {
    const int *jlist = firstneigh[ilist[ii]];
    for (int jj = 0, n = numneigh[ilist[ii]]; jj < n; jj++) {
      const int j = jlist[jj] & neighmask;
      if (j < nreceive) as_j_[fill[j]++] = offset_[ii] + std::size_t(jj);
    }
  }
  terms_.resize(npairs());
  contact_.assign(npairs(), 0);
}

void PairForceGather::clear_contacts(int ii_from, int ii_to)
{
  if (ii_to > ii_from) std::memset(&contact_[offset_[ii_from]], 0, offset_[ii_to] - offset_[ii_from]);
}

void PairForceGather::gather(int k_from, int k_to, double **f, double **torque) const
{
  for (int k = k_from; k < k_to; k++) {
    const std::size_t *q = as_j_.data() + as_j_start_[k], *qend = as_j_.data() + as_j_start_[k + 1];
    const int ii = list_pos_[k];
    const std::size_t own_begin = ii >= 0 ? offset_[ii] : 0, own_end = ii >= 0 ? offset_[ii + 1] : 0;
    if (q == qend && own_begin == own_end) continue;
    double fk[3] = {f[k][0], f[k][1], f[k][2]}, tk[3] = {torque[k][0], torque[k][1], torque[k][2]};
    auto add_as_j = [&](std::size_t p) {
      if (!contact_[p]) return;
      const PairTerms &t = terms_[p];
      for (int c = 0; c < 3; c++) {
        fk[c] -= t.F[c];
        tk[c] += t.Tj[c];
      }
    };
    // the serial loop reaches atom k's pairs in slot order: those of earlier list atoms (k as j),
    // then k's own row, then those of later list atoms
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
  return offset_.capacity() * sizeof(std::size_t) + list_pos_.capacity() * sizeof(int) +
         as_j_start_.capacity() * sizeof(std::size_t) + as_j_.capacity() * sizeof(std::size_t) +
         terms_.capacity() * sizeof(PairTerms) + contact_.capacity();
}

}  // namespace dembridge::threads
