#include "fix_contact_history.h"

#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "neigh_list.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <unordered_map>

#if defined(_OPENMP)
#include <omp.h>
#endif

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;

namespace dembridge {

// The threads `package omp N` asks for share the per-rebuild conversions (results do not depend on it).
static int conversion_threads(LAMMPS *lmp)
{
#if defined(_OPENMP)
  return std::max(1, lmp->comm->nthreads);
#else
  (void)lmp;
  return 1;
#endif
}

// Runs body(t) for t in [0, nparts) on up to nparts threads; each t exactly once.
template <class Body> static void for_each_part(int nparts, Body &&body)
{
#if defined(_OPENMP)
#pragma omp parallel num_threads(nparts) if (nparts > 1)
  {
    for (int t = omp_get_thread_num(); t < nparts; t += omp_get_num_threads()) body(t);
  }
#else
  for (int t = 0; t < nparts; t++) body(t);
#endif
}

// Sizes v for n elements whose old values are not read again. A vector that must grow is released first
// (resize would copy the old values into a new block while the old one still exists: both at once at the
// memory peak), then given 1/16 more than n, so that a list growing by a few entries per rebuild or an atom
// arriving by exchange rarely reallocates (the extra is never written, so it is not resident); a block more
// than twice what is needed is released too. The elements of the result are unspecified.
template <class T> static void resize_discarding(std::vector<T> &v, std::size_t n, std::size_t slack)
{
  if (n > v.capacity() || v.capacity() > 2 * n + slack) {
    std::vector<T>().swap(v);
    v.reserve(n + n / 16);
  }
  v.resize(n);
}

// NVALUES 0 is a placeholder: the pair style reserves its place in the fix order when pair_style
// is read (fixes run in definition order, and the history must be converted before a later
// fix pour inserts atoms) and replaces it, in place, by the real fix at init.
static int history_values(LAMMPS *lmp, int narg, char **arg)
{
  if (narg != 4) lmp->error->all(FLERR, "fix dembridge/contact/history is internal to the dembridge pair styles");
  const int nv = utils::inumeric(FLERR, arg[3], false, lmp);
  if (nv < 0) lmp->error->all(FLERR, "fix dembridge/contact/history: number of values must be >= 0");
  return nv;
}

FixContactHistory::FixContactHistory(LAMMPS *lmp, int narg, char **arg) :
    PerAtomCallbacksFix(lmp, narg, arg), nv_(history_values(lmp, narg, arg)), partners_(nv_, &atom->tag)
{
  if (nv_ == 0) return;
  attach(partners_);
  maxexchange_dynamic = 1;
  set_maxexchange(0);
  vector_flag = 1;
  size_vector = 4;
  global_freq = 1;
  extvector = 0;
  for (int i = 0; i < atom->nlocal; i++) partners_.own_tag[i] = atom->tag ? atom->tag[i] : 0;
}

int FixContactHistory::setmask()
{
  if (nv_ == 0) return 0;
  return PRE_EXCHANGE | POST_NEIGHBOR | MIN_PRE_EXCHANGE | MIN_POST_NEIGHBOR;
}

void FixContactHistory::set_maxexchange(int most_partners)
{
  maxexchange = 1 + most_partners * (1 + nv_);
}

// Atoms are about to move between ranks or be re-indexed: the per-atom lists become the truth.
void FixContactHistory::pre_exchange()
{
  sync_atoms();
  list_valid_ = false;
}

// Start of a run or minimisation: atoms may have been deleted, created or renumbered since.
void FixContactHistory::setup_pre_exchange()
{
  sync_atoms();
  follow_renumbered_tags();
  list_valid_ = false;
}

void FixContactHistory::post_neighbor()
{
  list_from_atoms();
  list_valid_ = true;
  atoms_stale_ = false;
  compact_pool();
}

// Keep per-atom lists current between runs (restart files, atom changes before the next run).
// The list-order slots stay valid too, so a following `run N pre no` (no setup, no neighbour
// rebuild) continues with them.
void FixContactHistory::post_run()
{
  sync_atoms();
}

// List order -> per-atom lists. The list's atoms are named by the tags it was built with, and
// found again by tag if a fix before this one inserted or deleted atoms in this pre_exchange.
void FixContactHistory::atoms_from_list()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  const int nold = list_nlocal_;

  // where the list's atom i is now (-1: deleted); no table when nothing changed (the usual case)
  std::vector<int> moved;
  if (nlocal != nold || !std::equal(tag, tag + nlocal, list_tag_.begin())) {
    moved.resize(nold);
    std::unordered_map<tagint, int> where(2 * std::size_t(nlocal));
    for (int i = 0; i < nlocal; i++) where.emplace(tag[i], i);
    for (int i = 0; i < nold; i++) {
      auto it = where.find(list_tag_[i]);
      moved[i] = it == where.end() ? -1 : it->second;
    }
  }
  const int *now = moved.empty() ? nullptr : moved.data();
  auto index_now = [now](int i) { return now ? now[i] : i; };

  // Two passes over the same traversal, count then fill (keeps each atom's partner order): each
  // touched slot (i, jj) gives i its spring and the owned partner j the mirrored one. With threads,
  // part t of the list rows counts, then fills, its own run of every atom's entries; runs of
  // earlier parts come first, so the entries are those of one pass over the whole list, in order.
  const int *ilist = list_->ilist, *numneigh = list_->numneigh;
  const int inum = list_->inum;
  auto for_each_contact = [&](int ii_begin, int ii_end, auto &&visit) {
    for (int ii = ii_begin; ii < ii_end; ii++) {
      const int i = ilist[ii];
      const int *jlist = list_->firstneigh[i];
      for (int jj = 0; jj < numneigh[i]; jj++) {
        if (touched(i, jj) == gran::TouchFlag::Separated) continue;
        const int j = jlist[jj] & NEIGHMASK;
        const int a = index_now(i);
        if (a >= 0) visit(a, list_tag_[j], slot(i, jj), 1.0);
        if (j < nold && index_now(j) >= 0) visit(index_now(j), list_tag_[i], slot(i, jj), -1.0);
      }
    }
  };
  const int nparts = std::min(conversion_threads(lmp), std::max(1, inum));
  auto rows = [&](int t) { return int(std::int64_t(inum) * t / nparts); };
  // part t's count per atom, then the atom's fill position relative to its run
  std::vector<int> next(std::size_t(nparts) * std::size_t(nlocal), 0);
  for_each_part(nparts, [&](int t) {
    int *n = next.data() + std::size_t(t) * nlocal;
    for_each_contact(rows(t), rows(t + 1), [&](int a, tagint, const double *, double) { n[a]++; });
  });
  std::size_t total = 0;
  int most = 0;
  for (int a = 0; a < nlocal; a++) {
    partners_.offset[a] = total;
    partners_.own_tag[a] = tag[a];
    int count = 0;
    for (int t = 0; t < nparts; t++) {
      int &n = next[std::size_t(t) * nlocal + a];
      const int part_count = n;
      n = count;
      count += part_count;
    }
    partners_.npartner[a] = count;
    total += std::size_t(count);
    most = std::max(most, count);
  }
  // The old runs are not read again (the list-order slots hold the history).
  resize_discarding(partners_.pool_tag, total, 1024);
  resize_discarding(partners_.pool_val, total * nv_, 1024 * std::size_t(nv_));
  for_each_part(nparts, [&](int t) {
    int *pos = next.data() + std::size_t(t) * nlocal;
    for_each_contact(rows(t), rows(t + 1), [&](int a, tagint partner, const double *v, double sign) {
      const std::size_t k = partners_.offset[a] + std::size_t(pos[a]++);
      partners_.pool_tag[k] = partner;
      for (int m = 0; m < nv_; m++) partners_.pool_val[k * nv_ + m] = sign * v[m];
    });
  });
  set_maxexchange(most);
  atoms_stale_ = false;
}

void FixContactHistory::list_from_atoms()
{
  if (!list_) error->all(FLERR, "fix dembridge/contact/history: no neighbour list (internal error)");
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  const int *ilist = list_->ilist, *numneigh = list_->numneigh;
  std::size_t total = 0;
  resize_discarding(first_, nlocal, 1024);
  std::fill(first_.begin(), first_.end(), 0);
  for (int ii = 0; ii < list_->inum; ii++) {
    const int i = ilist[ii];
    first_[i] = total;
    total += numneigh[i];
  }
  // The old slots were copied to the per-atom lists at pre_exchange. Every slot belongs to one row,
  // which clears it: rows are independent, shared by the threads.
  resize_discarding(values_, total * nv_, 4096);
  // kTouchPadding flags more than the slots: the AVX2 overlap scan reads four flags at once, also at
  // an atom's last one to three neighbours (pair_gran_scan.h), and ignores what lies past the list
  resize_discarding(touch_, total + gran::kTouchPadding, 4096);
  slots_ = total;
  const int inum = list_->inum;
  [[maybe_unused]] const int nthreads = conversion_threads(lmp);  // used by the OpenMP pragma only
#if defined(_OPENMP)
#pragma omp parallel for num_threads(nthreads) schedule(static) if (nthreads > 1 && inum > 1)
#endif
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    std::fill_n(values_.begin() + first_[i] * nv_, std::size_t(numneigh[i]) * nv_, 0.0);
    std::fill_n(touch_.begin() + first_[i], numneigh[i], gran::TouchFlag::Separated);
    if (partners_.npartner[i] == 0) continue;
    const int *jlist = list_->firstneigh[i];
    const std::size_t base = partners_.offset[i];
    for (int jj = 0; jj < numneigh[i]; jj++) {
      const tagint tj = tag[jlist[jj] & NEIGHMASK];
      for (int k = 0; k < partners_.npartner[i]; k++) {
        if (partners_.pool_tag[base + k] != tj) continue;
        std::memcpy(slot(i, jj), &partners_.pool_val[(base + k) * nv_], nv_ * sizeof(double));
        touched(i, jj) = gran::TouchFlag::Touching;
        break;
      }
    }
  }
  resize_discarding(list_tag_, nall, 1024);
  std::copy(tag, tag + nall, list_tag_.begin());
  list_nlocal_ = nlocal;
}

std::size_t FixContactHistory::live_entries() const
{
  std::size_t n = 0;
  for (int i = 0; i < atom->nlocal; i++) n += partners_.npartner[i];
  return n;
}

// Exchanges and restarts append to the pool; keep it within twice the entries in use.
void FixContactHistory::compact_pool()
{
  const std::size_t live = live_entries();
  if (partners_.pool_tag.size() <= 2 * live + 1024) return;
  std::vector<tagint> ptag(live);
  std::vector<double> pval(live * nv_);
  std::size_t k = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    std::copy_n(&partners_.pool_tag[partners_.offset[i]], partners_.npartner[i], &ptag[k]);
    std::copy_n(&partners_.pool_val[partners_.offset[i] * nv_], partners_.npartner[i] * nv_, &pval[k * nv_]);
    partners_.offset[i] = k;
    k += partners_.npartner[i];
  }
  partners_.pool_tag.swap(ptag);
  partners_.pool_val.swap(pval);
}

// delete_atoms (compress yes) and reset_atoms id renumber atoms between runs: partner tags are
// translated to the new IDs, partners that no longer exist are dropped.
void FixContactHistory::follow_renumbered_tags()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  int changed = 0, any = 0;
  for (int i = 0; i < nlocal && !changed; i++) changed = partners_.own_tag[i] != 0 && partners_.own_tag[i] != tag[i];
  MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, world);
  if (!any) return;

  std::vector<tagint> mine;  // (old, new) of every atom whose list this rank holds
  for (int i = 0; i < nlocal; i++)
    if (partners_.own_tag[i] != 0) {
      mine.push_back(partners_.own_tag[i]);
      mine.push_back(tag[i]);
    }
  int n = int(mine.size());
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < comm->nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<tagint> all(std::size_t(displs.back()) + counts.back());
  MPI_Allgatherv(mine.data(), n, MPI_LMP_TAGINT, all.data(), counts.data(), displs.data(), MPI_LMP_TAGINT, world);
  std::unordered_map<tagint, tagint> renamed(all.size());
  for (std::size_t k = 0; k + 1 < all.size(); k += 2) renamed.emplace(all[k], all[k + 1]);

  std::vector<tagint> ptag;
  std::vector<double> pval;
  for (int i = 0; i < nlocal; i++) {
    const std::size_t base = partners_.offset[i], start = ptag.size();
    for (int k = 0; k < partners_.npartner[i]; k++) {
      auto it = renamed.find(partners_.pool_tag[base + k]);
      if (it == renamed.end()) continue;
      ptag.push_back(it->second);
      pval.insert(pval.end(), &partners_.pool_val[(base + k) * nv_], &partners_.pool_val[(base + k + 1) * nv_]);
    }
    partners_.offset[i] = start;
    partners_.npartner[i] = int(ptag.size() - start);
    partners_.own_tag[i] = tag[i];
  }
  partners_.pool_tag.swap(ptag);
  partners_.pool_val.swap(pval);
}

// A restart written mid-run needs the per-atom lists of this step.
void FixContactHistory::sync_atoms()
{
  if (list_valid_ && atoms_stale_) atoms_from_list();
}

void FixContactHistory::check_restored(int)
{
  list_valid_ = false;
}

// A pair style given again after read_restart with another model stores another number of values per
// contact: its springs start from zero (LAMMPS's restart data has no other use).
void FixContactHistory::restart_mismatch(int i)
{
  if (!mismatch_warned_ && comm->me == 0)
    error->warning(FLERR, "fix dembridge/contact/history: the restart file holds another number of history values per "
                          "contact than the pair style now uses; contact history restarts from zero");
  mismatch_warned_ = true;
  partners_.clear(i);
  partners_.own_tag[i] = atom->tag[i];
}

// Entries a conversion of the current list-order slots gives the per-atom lists: each touched slot
// gives one to its atom and one to its partner when the partner is owned.
std::size_t FixContactHistory::list_entries() const
{
  std::size_t n = 0;
  for (int ii = 0; ii < list_->inum; ii++) {
    const int i = list_->ilist[ii];
    const int *jlist = list_->firstneigh[i];
    for (int jj = 0; jj < list_->numneigh[i]; jj++)
      if (touch_[first_[i] + jj] != gran::TouchFlag::Separated) n += 1 + ((jlist[jj] & NEIGHMASK) < list_nlocal_);
  }
  return n;
}

// Bytes in use (the spare capacity resize_discarding leaves is never written, so it is not resident):
// the list-order slots and, for `entries` entries, the per-atom lists.
double FixContactHistory::contact_bytes(std::size_t entries) const
{
  return double(values_.size()) * sizeof(double) + double(touch_.size()) + double(entries) * (sizeof(tagint) + nv_ * sizeof(double));
}

// LAMMPS's memory line: the contact storage with the per-atom lists as large as the contacts present
// need (they are rebuilt from the list-order slots at every re-neighbouring, the first time at the
// first one after the line is printed), and the per-atom index.
double FixContactHistory::memory_usage()
{
  const std::size_t entries = std::max(partners_.pool_tag.size(), list_valid_ ? list_entries() : 0);
  return contact_bytes(entries) + double(first_.size()) * sizeof(std::size_t) + double(list_tag_.size()) * sizeof(tagint) +
      double(partners_.npartner.size()) * sizeof(int) + double(partners_.offset.size()) * sizeof(std::size_t) +
      double(partners_.own_tag.size()) * sizeof(tagint);
}

// [1] bytes in use (memory_usage), [2] contacts stored (each is kept by both atoms), [3] list-order
// slots, [4] bytes of the contact storage alone (per-atom lists and list-order slots, without the
// per-atom index arrays, which follow the atom count); all ranks.
double FixContactHistory::compute_vector(int n)
{
  sync_atoms();
  double local[4] = {memory_usage(), 0.5 * double(live_entries()), double(slots_), contact_bytes(partners_.pool_tag.size())};
  MPI_Allreduce(local, stats_, 4, MPI_DOUBLE, MPI_SUM, world);
  return stats_[n];
}

static void *create_fix_contact_history(void *lmp, int narg, char **arg)
{
  return new FixContactHistory(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_contact_history("fix", "dembridge/contact/history",
                                             "per-contact history of the dembridge granular pair styles (internal)",
                                             create_fix_contact_history);

}  // namespace dembridge
