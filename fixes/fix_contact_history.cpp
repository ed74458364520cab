#include "fix_contact_history.h"

#include "style_registry.h"

#include "atom.h"
#include "error.h"
#include "neigh_list.h"

#include <algorithm>
#include <cstring>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;

namespace dembridge {

FixContactHistory::FixContactHistory(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg != 4) error->all(FLERR, "fix dembridge/contact/history is internal to the dembridge pair styles");
  nv_ = utils::inumeric(FLERR, arg[3], false, lmp);
  if (nv_ < 1) error->all(FLERR, "fix dembridge/contact/history: number of values must be >= 1");
  restart_peratom = 1;
  create_attribute = 1;
  maxexchange_dynamic = 1;
  maxexchange = 1 + cap_ * (1 + nv_);
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; i++) npartner_[i] = 0;
}

FixContactHistory::~FixContactHistory()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
}

int FixContactHistory::setmask()
{
  return PRE_EXCHANGE | POST_NEIGHBOR | MIN_PRE_EXCHANGE | MIN_POST_NEIGHBOR;
}

// Atoms are about to move between ranks or be re-indexed: the per-atom lists become the truth.
void FixContactHistory::pre_exchange()
{
  sync_atoms();
  list_valid_ = false;
}

void FixContactHistory::post_neighbor()
{
  list_from_atoms();
  list_valid_ = true;
  atoms_stale_ = false;
}

// Keep per-atom lists current between runs (restart files, atom changes before the next run).
// The list-order slots stay valid too, so a following `run N pre no` (no setup, no neighbour
// rebuild) continues with them.
void FixContactHistory::post_run()
{
  sync_atoms();
}

void FixContactHistory::add_partner(int i, tagint tag, const double *v, double sign)
{
  if (npartner_[i] == cap_) grow_capacity(cap_ * 2);
  const std::size_t k = std::size_t(i) * cap_ + npartner_[i];
  partner_[k] = tag;
  for (int m = 0; m < nv_; m++) pvalues_[k * nv_ + m] = sign * v[m];
  npartner_[i]++;
}

void FixContactHistory::atoms_from_list()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  std::fill(npartner_.begin(), npartner_.begin() + nlocal, 0);
  const int *ilist = list_->ilist, *numneigh = list_->numneigh;
  for (int ii = 0; ii < list_->inum; ii++) {
    const int i = ilist[ii];
    const int *jlist = list_->firstneigh[i];
    for (int jj = 0; jj < numneigh[i]; jj++) {
      if (!touched(i, jj)) continue;
      const int j = jlist[jj] & NEIGHMASK;
      const double *v = slot(i, jj);
      add_partner(i, tag[j], v, 1.0);
      if (j < nlocal) add_partner(j, tag[i], v, -1.0);  // the partner sees the mirrored spring
    }
  }
  atoms_stale_ = false;
}

void FixContactHistory::list_from_atoms()
{
  if (!list_) error->all(FLERR, "fix dembridge/contact/history: no neighbour list (internal error)");
  const tagint *tag = atom->tag;
  const int *ilist = list_->ilist, *numneigh = list_->numneigh;
  std::size_t total = 0;
  first_.assign(atom->nmax, 0);
  for (int ii = 0; ii < list_->inum; ii++) {
    const int i = ilist[ii];
    first_[i] = total;
    total += numneigh[i];
  }
  values_.assign(total * nv_, 0.0);
  touch_.assign(total, 0);
  for (int ii = 0; ii < list_->inum; ii++) {
    const int i = ilist[ii];
    if (npartner_[i] == 0) continue;
    const int *jlist = list_->firstneigh[i];
    const std::size_t base = std::size_t(i) * cap_;
    for (int jj = 0; jj < numneigh[i]; jj++) {
      const tagint tj = tag[jlist[jj] & NEIGHMASK];
      for (int k = 0; k < npartner_[i]; k++) {
        if (partner_[base + k] != tj) continue;
        std::memcpy(slot(i, jj), &pvalues_[(base + k) * nv_], nv_ * sizeof(double));
        touched(i, jj) = 1;
        break;
      }
    }
  }
}

void FixContactHistory::grow_capacity(int need)
{
  const int newcap = std::max(need, cap_);
  std::vector<tagint> p(std::size_t(nmax_) * newcap);
  std::vector<double> v(std::size_t(nmax_) * newcap * nv_);
  for (int i = 0; i < nmax_; i++)
    for (int k = 0; k < npartner_[i]; k++) {
      p[std::size_t(i) * newcap + k] = partner_[std::size_t(i) * cap_ + k];
      std::memcpy(&v[(std::size_t(i) * newcap + k) * nv_], &pvalues_[(std::size_t(i) * cap_ + k) * nv_], nv_ * sizeof(double));
    }
  partner_.swap(p);
  pvalues_.swap(v);
  cap_ = newcap;
  maxexchange = 1 + cap_ * (1 + nv_);
}

void FixContactHistory::grow_arrays(int nmax)
{
  npartner_.resize(nmax, 0);
  partner_.resize(std::size_t(nmax) * cap_);
  pvalues_.resize(std::size_t(nmax) * cap_ * nv_);
  nmax_ = nmax;
}

void FixContactHistory::copy_arrays(int i, int j, int /*delflag*/)
{
  npartner_[j] = npartner_[i];
  std::copy_n(&partner_[std::size_t(i) * cap_], npartner_[i], &partner_[std::size_t(j) * cap_]);
  std::copy_n(&pvalues_[std::size_t(i) * cap_ * nv_], npartner_[i] * nv_, &pvalues_[std::size_t(j) * cap_ * nv_]);
}

// Partner list of atom i as [n, tag_1, values_1..., tag_n, values_n...]; shared by exchange and restart.
int FixContactHistory::pack_partners(int i, double *buf) const
{
  int m = 0;
  buf[m++] = npartner_[i];
  for (int k = 0; k < npartner_[i]; k++) {
    buf[m++] = ubuf(partner_[std::size_t(i) * cap_ + k]).d;
    for (int q = 0; q < nv_; q++) buf[m++] = pvalues_[(std::size_t(i) * cap_ + k) * nv_ + q];
  }
  return m;
}

int FixContactHistory::unpack_partners(int i, const double *buf)
{
  int m = 0;
  const int n = static_cast<int>(buf[m++]);
  if (n > cap_) grow_capacity(n);
  npartner_[i] = n;
  for (int k = 0; k < n; k++) {
    partner_[std::size_t(i) * cap_ + k] = static_cast<tagint>(ubuf(buf[m++]).i);
    for (int q = 0; q < nv_; q++) pvalues_[(std::size_t(i) * cap_ + k) * nv_ + q] = buf[m++];
  }
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
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  unpack_partners(nlocal, &extra[nlocal][m + 1]);
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
  return double(values_.capacity()) * sizeof(double) + touch_.capacity() + first_.capacity() * sizeof(int) +
      pvalues_.capacity() * sizeof(double) + partner_.capacity() * sizeof(tagint) + npartner_.capacity() * sizeof(int);
}

static void *create_fix_contact_history(void *lmp, int narg, char **arg)
{
  return new FixContactHistory(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_contact_history("fix", "dembridge/contact/history",
                                             "per-contact history of the dembridge granular pair styles (internal)",
                                             create_fix_contact_history);

}  // namespace dembridge
