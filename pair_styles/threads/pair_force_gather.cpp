#include "pair_force_gather.h"

#include <algorithm>
#include <cstring>

namespace dembridge::threads {

// first_block_ holds block numbers in 16 bits
static constexpr int kMaxBlocks = 65535;

void PairForceGather::index(int inum, const int *ilist, const int *numneigh, int nreceive, int nblocks, const double *row_weight)
{
  nreceive_ = nreceive;
  nblocks = std::clamp(nblocks, 1, kMaxBlocks);
  offset_.resize(std::size_t(inum) + 1);
  offset_[0] = 0;
  for (int ii = 0; ii < inum; ii++) offset_[ii + 1] = offset_[ii] + std::size_t(numneigh[ilist[ii]]);
  // blocks of about equal work (by default: entries, not atoms)
  std::vector<double> work(std::size_t(inum) + 1, 0.0);
  for (int ii = 0; ii < inum; ii++) work[ii + 1] = work[ii] + (row_weight ? row_weight[ii] : double(numneigh[ilist[ii]]));
  block_.assign(std::size_t(nblocks) + 1, inum);
  block_[0] = 0;
  for (int b = 1; b < nblocks; b++)
    block_[b] = int(std::lower_bound(work.begin(), work.end() - 1, work[inum] * b / nblocks) - work.begin());
  named_.resize(std::size_t(nblocks) * std::size_t(nreceive));
  first_block_.resize(std::size_t(nreceive));
  log_.resize(std::size_t(nblocks));
  kept_F_.resize(3 * npairs());
  kept_.assign(npairs(), 0);
}

void PairForceGather::mark_block(int b, const int *ilist, const int *numneigh, int *const *firstneigh, int neighmask)
{
  unsigned char *named = named_.data() + std::size_t(b) * std::size_t(nreceive_);
  std::memset(named, 0, std::size_t(nreceive_));
  for (int ii = block_[b]; ii < block_[b + 1]; ii++) {
    const int i = ilist[ii];
    named[i] = 1;
    const int *jlist = firstneigh[i];
    for (int jj = 0, n = numneigh[i]; jj < n; jj++) {
      const int j = jlist[jj] & neighmask;
      if (j < nreceive_) named[j] = 1;
    }
  }
}

void PairForceGather::resolve(int from, int to)
{
  const int nb = nblocks();
  for (int k = from; k < to; k++) {
    int b = 0;
    while (b < nb && !named_[std::size_t(b) * std::size_t(nreceive_) + k]) b++;
    first_block_[k] = static_cast<std::uint16_t>(b);  // nb: named by no block
  }
}

void PairForceGather::build(int inum, const int *ilist, const int *numneigh, int *const *firstneigh, int neighmask, int nreceive,
                            int nblocks, const double *row_weight)
{
  index(inum, ilist, numneigh, nreceive, nblocks, row_weight);
  for (int b = 0; b < this->nblocks(); b++) mark_block(b, ilist, numneigh, firstneigh, neighmask);
  resolve(0, nreceive);
}

int PairForceGather::ndeferred_atoms(int b) const
{
  int n = 0;
  const unsigned char *named = named_.data() + std::size_t(b) * std::size_t(nreceive_);
  for (int k = 0; k < nreceive_; k++) n += named[k] && first_block_[k] < b;
  return n;
}

void PairForceGather::begin_block(int b, bool keep_all)
{
  log_[b].terms.clear();
  if (keep_all && block_[b + 1] > block_[b])
    std::memset(&kept_[offset_[block_[b]]], 0, offset_[block_[b + 1]] - offset_[block_[b]]);
}

void PairForceGather::apply_deferred(int part, int nparts, double *f, double *torque) const
{
  for (int b = 1; b < nblocks(); b++)
    for (const Deferred &d : log_[b].terms) {
      if (d.k % nparts != part) continue;
      for (int c = 0; c < 3; c++) {
        f[3 * d.k + c] += d.F[c];
        torque[3 * d.k + c] += d.T[c];
      }
    }
}

std::size_t PairForceGather::memory_bytes() const
{
  std::size_t logs = log_.capacity() * sizeof(Log);
  for (const Log &l : log_) logs += l.terms.capacity() * sizeof(Deferred);
  return block_.capacity() * sizeof(int) + offset_.capacity() * sizeof(std::size_t) + named_.capacity() +
      first_block_.capacity() * sizeof(std::uint16_t) + logs + kept_F_.capacity() * sizeof(double) + kept_.capacity();
}

}  // namespace dembridge::threads
