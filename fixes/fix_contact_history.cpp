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

// NVALUES 0 is a placeholder: the pair style reserves its place in the fix order when pair_style
// is read (fixes run in definition order, and the history must be converted before a later
// fix pour inserts atoms) and replaces it, in place, by the real fix at init.
FixContactHistory::FixContactHistory(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg != 4) error->all(FLERR, "fix dembridge/contact/history is internal to the dembridge pair styles");
  nv_ = utils::inumeric(FLERR, arg[3], false, lmp);
  if (nv_ < 0) error->all(FLERR, "fix dembridge/contact/history: number of values must be >= 0");
  if (nv_ == 0) return;
  restart_peratom = 1;
  create_attribute = 1;
  maxexchange_dynamic = 1;
  set_maxexchange(0);
  vector_flag = 1;
  size_vector = 4;
  global_freq = 1;
  extvector = 0;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; i++) {
    set_arrays(i);
    own_tag_[i] = atom->tag ? atom->tag[i] : 0;
  }
}

FixContactHistory::~FixContactHistory()
{
  if (nv_ == 0) return;
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
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

  std::vector<int> now(nold);
  const bool unchanged = nlocal == nold && std::equal(tag, tag + nlocal, list_tag_.begin());
  if (unchanged) {
    for (int i = 0; i < nold; i++) now[i] = i;
  } else {
    std::unordered_map<tagint, int> where(2 * std::size_t(nlocal));
    for (int i = 0; i < nlocal; i++) where.emplace(tag[i], i);
    for (int i = 0; i < nold; i++) {
      auto it = where.find(list_tag_[i]);
      now[i] = it == where.end() ? -1 : it->second;  // -1: deleted
    }
  }

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
        if (now[i] >= 0) visit(now[i], list_tag_[j], slot(i, jj), 1.0);
        if (j < nold && now[j] >= 0) visit(now[j], list_tag_[i], slot(i, jj), -1.0);
      }
    }
  };
  const int nparts = std::min(conversion_threads(lmp), std::max(1, inum));
  auto rows = [&](int t) { return int(std::int64_t(inum) * t / nparts); };
  std::vector<std::size_t> next(std::size_t(nparts) * std::size_t(nlocal), 0);  // part t's count, then fill position, per atom
  for_each_part(nparts, [&](int t) {
    std::size_t *n = next.data() + std::size_t(t) * nlocal;
    for_each_contact(rows(t), rows(t + 1), [&](int a, tagint, const double *, double) { n[a]++; });
  });
  std::size_t total = 0;
  int most = 0;
  for (int a = 0; a < nlocal; a++) {
    offset_[a] = total;
    own_tag_[a] = tag[a];
    std::size_t count = 0;
    for (int t = 0; t < nparts; t++) {
      std::size_t &n = next[std::size_t(t) * nlocal + a];
      const std::size_t part_count = n;
      n = total + count;
      count += part_count;
    }
    npartner_[a] = int(count);
    total += count;
    most = std::max(most, int(count));
  }
  // The old runs are not read again (the list-order slots hold the history): reuse the pool's
  // storage, released when it is more than twice what the contacts present need.
  if (pool_tag_.capacity() > 2 * total + 1024) {
    std::vector<tagint>().swap(pool_tag_);
    std::vector<double>().swap(pool_val_);
  }
  pool_tag_.resize(total);
  pool_val_.resize(total * nv_);
  for_each_part(nparts, [&](int t) {
    std::size_t *pos = next.data() + std::size_t(t) * nlocal;
    for_each_contact(rows(t), rows(t + 1), [&](int a, tagint partner, const double *v, double sign) {
      const std::size_t k = pos[a]++;
      pool_tag_[k] = partner;
      for (int m = 0; m < nv_; m++) pool_val_[k * nv_ + m] = sign * v[m];
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
  first_.assign(nlocal, 0);
  for (int ii = 0; ii < list_->inum; ii++) {
    const int i = ilist[ii];
    first_[i] = total;
    total += numneigh[i];
  }
  // release the storage of a denser past (assign never shrinks a vector)
  if (values_.capacity() > 2 * total * nv_ + 4096) std::vector<double>().swap(values_);
  if (touch_.capacity() > 2 * total + 4096) std::vector<gran::TouchFlag>().swap(touch_);
  // every slot belongs to one row, which clears it: rows are independent, shared by the threads
  values_.resize(total * nv_);
  touch_.resize(total);
  const int inum = list_->inum;
  [[maybe_unused]] const int nthreads = conversion_threads(lmp);  // used by the OpenMP pragma only
#if defined(_OPENMP)
#pragma omp parallel for num_threads(nthreads) schedule(static) if (nthreads > 1 && inum > 1)
#endif
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    std::fill_n(values_.begin() + first_[i] * nv_, std::size_t(numneigh[i]) * nv_, 0.0);
    std::fill_n(touch_.begin() + first_[i], numneigh[i], gran::TouchFlag::Separated);
    if (npartner_[i] == 0) continue;
    const int *jlist = list_->firstneigh[i];
    const std::size_t base = offset_[i];
    for (int jj = 0; jj < numneigh[i]; jj++) {
      const tagint tj = tag[jlist[jj] & NEIGHMASK];
      for (int k = 0; k < npartner_[i]; k++) {
        if (pool_tag_[base + k] != tj) continue;
        std::memcpy(slot(i, jj), &pool_val_[(base + k) * nv_], nv_ * sizeof(double));
        touched(i, jj) = gran::TouchFlag::Touching;
        break;
      }
    }
  }
  list_tag_.assign(tag, tag + nall);
  list_nlocal_ = nlocal;
}

std::size_t FixContactHistory::live_entries() const
{
  std::size_t n = 0;
  for (int i = 0; i < atom->nlocal; i++) n += npartner_[i];
  return n;
}

// Exchanges and restarts append to the pool; keep it within twice the entries in use.
void FixContactHistory::compact_pool()
{
  const std::size_t live = live_entries();
  if (pool_tag_.size() <= 2 * live + 1024) return;
  std::vector<tagint> ptag(live);
  std::vector<double> pval(live * nv_);
  std::size_t k = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    std::copy_n(&pool_tag_[offset_[i]], npartner_[i], &ptag[k]);
    std::copy_n(&pool_val_[offset_[i] * nv_], npartner_[i] * nv_, &pval[k * nv_]);
    offset_[i] = k;
    k += npartner_[i];
  }
  pool_tag_.swap(ptag);
  pool_val_.swap(pval);
}

// delete_atoms (compress yes) and reset_atoms id renumber atoms between runs: partner tags are
// translated to the new IDs, partners that no longer exist are dropped.
void FixContactHistory::follow_renumbered_tags()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  int changed = 0, any = 0;
  for (int i = 0; i < nlocal && !changed; i++) changed = own_tag_[i] != 0 && own_tag_[i] != tag[i];
  MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, world);
  if (!any) return;

  std::vector<tagint> mine;  // (old, new) of every atom whose list this rank holds
  for (int i = 0; i < nlocal; i++)
    if (own_tag_[i] != 0) {
      mine.push_back(own_tag_[i]);
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
    const std::size_t base = offset_[i], start = ptag.size();
    for (int k = 0; k < npartner_[i]; k++) {
      auto it = renamed.find(pool_tag_[base + k]);
      if (it == renamed.end()) continue;
      ptag.push_back(it->second);
      pval.insert(pval.end(), &pool_val_[(base + k) * nv_], &pool_val_[(base + k + 1) * nv_]);
    }
    offset_[i] = start;
    npartner_[i] = int(ptag.size() - start);
    own_tag_[i] = tag[i];
  }
  pool_tag_.swap(ptag);
  pool_val_.swap(pval);
}

void FixContactHistory::grow_arrays(int nmax)
{
  npartner_.resize(nmax, 0);
  offset_.resize(nmax, 0);
  own_tag_.resize(nmax, 0);
}

// Copies share the source's run of the pool (runs are never modified, only rebuilt).
void FixContactHistory::copy_arrays(int i, int j, int /*delflag*/)
{
  npartner_[j] = npartner_[i];
  offset_[j] = offset_[i];
  own_tag_[j] = own_tag_[i];
}

void FixContactHistory::set_arrays(int i)
{
  npartner_[i] = 0;
  offset_[i] = 0;
  own_tag_[i] = 0;  // a new atom: its tag may not be assigned yet, and it has no partners
}

// Partner list of atom i as [n, tag_1, values_1..., tag_n, values_n...]; shared by exchange and restart.
int FixContactHistory::pack_partners(int i, double *buf) const
{
  int m = 0;
  buf[m++] = npartner_[i];
  for (int k = 0; k < npartner_[i]; k++) {
    buf[m++] = ubuf(pool_tag_[offset_[i] + k]).d;
    for (int q = 0; q < nv_; q++) buf[m++] = pool_val_[(offset_[i] + k) * nv_ + q];
  }
  return m;
}

int FixContactHistory::unpack_partners(int i, const double *buf)
{
  int m = 0;
  const int n = static_cast<int>(buf[m++]);
  npartner_[i] = n;
  offset_[i] = pool_tag_.size();
  for (int k = 0; k < n; k++) {
    pool_tag_.push_back(static_cast<tagint>(ubuf(buf[m++]).i));
    for (int q = 0; q < nv_; q++) pool_val_.push_back(buf[m++]);
  }
  if (1 + n * (1 + nv_) > maxexchange) set_maxexchange(n);
  own_tag_[i] = atom->tag[i];
  return m;
}

int FixContactHistory::pack_exchange(int i, double *buf)
{
  return pack_partners(i, buf);
}

int FixContactHistory::unpack_exchange(int nlocal, double *buf)
{
  return unpack_partners(nlocal, buf);
}

// A restart written mid-run needs the per-atom lists of this step.
void FixContactHistory::sync_atoms()
{
  if (list_valid_ && atoms_stale_) atoms_from_list();
}

int FixContactHistory::size_restart(int i)
{
  sync_atoms();
  return 2 + npartner_[i] * (1 + nv_);
}

int FixContactHistory::pack_restart(int i, double *buf)
{
  sync_atoms();
  const int m = 1 + pack_partners(i, buf + 1);
  buf[0] = m;  // LAMMPS convention: the first value is the length of this fix's block
  return m;
}

void FixContactHistory::unpack_restart(int nlocal, int nth)
{
  // a placeholder (pair_style given again after read_restart) leaves the data to the real fix
  if (nv_ == 0) return;
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  const double *block = &extra[nlocal][m];
  // a pair style given again after read_restart with another model stores another number of
  // values per contact: its springs start from zero (LAMMPS's restart data has no other use)
  const int n = static_cast<int>(block[1]);
  if (static_cast<int>(block[0]) != 2 + n * (1 + nv_)) {
    if (!mismatch_warned_ && comm->me == 0)
      error->warning(FLERR, "fix dembridge/contact/history: the restart file holds another number of history values per "
                            "contact than the pair style now uses; contact history restarts from zero");
    mismatch_warned_ = true;
    set_arrays(nlocal);
    own_tag_[nlocal] = atom->tag[nlocal];
    return;
  }
  unpack_partners(nlocal, block + 1);
  list_valid_ = false;
}

int FixContactHistory::maxsize_restart()
{
  sync_atoms();
  int most = 0;
  for (int i = 0; i < atom->nlocal; i++) most = std::max(most, npartner_[i]);
  return 2 + most * (1 + nv_);
}

double FixContactHistory::memory_usage()
{
  return double(values_.capacity()) * sizeof(double) + touch_.capacity() + first_.capacity() * sizeof(std::size_t) +
      list_tag_.capacity() * sizeof(tagint) + pool_val_.capacity() * sizeof(double) + pool_tag_.capacity() * sizeof(tagint) +
      npartner_.capacity() * sizeof(int) + offset_.capacity() * sizeof(std::size_t) + own_tag_.capacity() * sizeof(tagint);
}

// [1] bytes held, [2] contacts stored (each is kept by both atoms), [3] list-order slots,
// [4] bytes of the contact storage alone (pool and list-order slots, without the per-atom index
// arrays, which follow the atom count); all ranks.
double FixContactHistory::compute_vector(int n)
{
  sync_atoms();
  const double contact_bytes = double(values_.capacity()) * sizeof(double) + touch_.capacity() +
      pool_val_.capacity() * sizeof(double) + pool_tag_.capacity() * sizeof(tagint);
  double local[4] = {memory_usage(), 0.5 * double(live_entries()), double(touch_.size()), contact_bytes};
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
