#include "compute_pair_gran_local.h"
#include "rank_error.h"

#include "fix_contact_history.h"
#include "pair_gran.h"
#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "update.h"

#include <algorithm>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;

namespace dembridge {

ComputePairGranLocal::ComputePairGranLocal(LAMMPS *lmp, int narg, char **arg) : Compute(lmp, narg, arg)
{
  const std::string me = "compute pair/gran/local (id " + std::string(id) + ")";
  for (int iarg = 3; iarg < narg; iarg++) {
    const std::string key = arg[iarg];
    if (key == "include") {
      if (iarg + 1 >= narg) error->all(FLERR, me + ": expected 'both' or 'either' after keyword 'include'");
      const std::string val = arg[++iarg];
      if (val == "both") either_ = false;
      else if (val == "either") either_ = true;
      else error->all(FLERR, me + ": expected 'both' or 'either' after keyword 'include', got '" + val + "'");
    } else {
      error->all(FLERR, me + ": unknown keyword '" + key +
                            "'; the columns are fixed (id_i id_j delta Fn Ft_x Ft_y Ft_z, then the history values), "
                            "LIGGGHTS column-selection keywords are not supported; the only keyword is 'include both|either'");
    }
  }
  // The columns must be known now (dump local checks c_ID[N] when it is defined), so the pair
  // style must exist already; init() checks that it has not been replaced by an incompatible one.
  PairGran *pair = dembridge_pair("when the compute is defined");
  nhist_ = pair->law().config().history_size();

  local_flag = 1;
  size_local_rows = 0;
  size_local_cols = kFixedCols + nhist_;
  array_local = nullptr;
  comm_forward = 6;  // v and omega of ghost atoms, into our own buffer (atom arrays untouched)
}

PairGran *ComputePairGranLocal::dembridge_pair(const char *when)
{
  const std::string me = "compute pair/gran/local (id " + std::string(id) + ")";
  if (!force->pair)
    error->all(FLERR, me + ": requires a dembridge granular pair style, but no pair style is defined " + when +
                          "; put the pair_style command before the compute");
  auto *pair = dynamic_cast<PairGran *>(force->pair);
  if (!pair)
    error->all(FLERR, me + ": pair style '" + std::string(force->pair_style) +
                          "' is not a dembridge granular pair style (gran/hooke, gran/hooke/history, gran/hertz/history, "
                          "their /stiffness variants, or gran model ...); pair_style hybrid is not supported");
  return pair;
}

void ComputePairGranLocal::init()
{
  PairGran *pair = dembridge_pair("at run setup");
  const int nh = pair->law().config().history_size();
  if (nh != nhist_)
    error->all(FLERR, "compute pair/gran/local (id " + std::string(id) + "): pair style '" + std::string(force->pair_style) +
                          "' has " + std::to_string(nh) + " history values per contact, but the compute was defined with " +
                          std::to_string(nhist_) + " history columns; define the compute again after the pair_style");
}

// Current v and omega of the ghost atoms. The pair's ghosts carry the values of the last forward
// communication (before the force evaluation); local atoms have since been advanced by the
// integrator. Refreshing them into a private buffer gives every row the same (current) state,
// whichever rank or periodic image holds the pair, and leaves atom->v/omega of ghosts untouched.
void ComputePairGranLocal::refresh_ghost_velocities()
{
  const std::size_t nall = std::size_t(atom->nlocal) + atom->nghost;
  if (ghost_vo_.size() < 6 * nall) ghost_vo_.resize(6 * nall);
  comm->forward_comm(this);
}

int ComputePairGranLocal::pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  const int nlocal = atom->nlocal;
  double **v = atom->v, **omega = atom->omega;
  const int *mask = atom->mask;
  double dv[3] = {0.0, 0.0, 0.0};
  const bool remap = pbc_flag && domain->deform_vremap;  // as AtomVec's velocity communication
  if (remap) {
    const double *h_rate = domain->h_rate;
    dv[0] = pbc[0] * h_rate[0] + pbc[5] * h_rate[5] + pbc[4] * h_rate[4];
    dv[1] = pbc[1] * h_rate[1] + pbc[3] * h_rate[3];
    dv[2] = pbc[2] * h_rate[2];
  }
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    // multi-hop exchanges forward ghosts received in an earlier swap: take those from the buffer
    const double *vj = j < nlocal ? v[j] : &ghost_vo_[6 * std::size_t(j)];
    const double *wj = j < nlocal ? omega[j] : &ghost_vo_[6 * std::size_t(j) + 3];
    const bool add = remap && (mask[j] & domain->deform_groupbit);
    for (int d = 0; d < 3; d++) buf[m++] = add ? vj[d] + dv[d] : vj[d];
    for (int d = 0; d < 3; d++) buf[m++] = wj[d];
  }
  return m;
}

void ComputePairGranLocal::unpack_forward_comm(int n, int first, double *buf)
{
  std::memcpy(&ghost_vo_[6 * std::size_t(first)], buf, sizeof(double) * 6 * std::size_t(n));
}

void ComputePairGranLocal::compute_local()
{
  invoked_local = update->ntimestep;
  const std::string me = "compute pair/gran/local (id " + std::string(id) + ")";
  // Between runs the neighbour list and the list-order history may no longer match the atoms
  // (the library's extract_compute, for one, invokes a compute that is not current).
  if (update->whichflag == 0)
    error->all(FLERR, me + ": invoked between runs; its rows are only computed during a run. Make it current on "
                          "the last step of the run (e.g. 'dump ID all local N file c_" + std::string(id) +
                          "[*]' with N dividing the step count, or a compute reduce of it in thermo output)");
  PairGran *pair = dembridge_pair("at this step");
  NeighList *list = pair->neighbor_list();
  if (!list) error->all(FLERR, me + ": the pair style has no neighbour list yet; the compute can only be used during a run");
  FixContactHistory *history = nhist_ > 0 ? pair->history() : nullptr;
  if (nhist_ > 0 && (!history || !history->list_valid()))
    fail_on_this_rank(lmp, FLERR, me + ": the contact history of pair style '" + std::string(force->pair_style) +
                                      "' is not aligned with the neighbour list at this point; use the compute only during a run "
                                      "(dump local, fix ave/histo, ...)");

  refresh_ghost_velocities();

  const gran::ContactLaw &law = pair->law();
  const gran::MaterialTable &table = pair->table();
  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  const double *radius = atom->radius;
  const int *type = atom->type, *mask = atom->mask;
  const tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  const int max_type = table.max_type();
  const double dt = update->dt;
  const int ncols = size_local_cols;

  auto vel = [&](int k) { return k < nlocal ? v[k] : &ghost_vo_[6 * std::size_t(k)]; };
  auto omg = [&](int k) { return k < nlocal ? omega[k] : &ghost_vo_[6 * std::size_t(k) + 3]; };

  data_.clear();
  gran::ContactResult res;
  double hist[6] = {0, 0, 0, 0, 0, 0};
  const int inum = list->inum;
  const int *ilist = list->ilist, *numneigh = list->numneigh;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const bool iin = mask[i] & groupbit;
    if (!iin && !either_) continue;
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const bool jin = mask[j] & groupbit;
      if (either_ ? !(iin || jin) : !(iin && jin)) continue;
      // Each contact once globally. newton on: the half list holds every pair once. newton off:
      // a pair with a ghost j is also in the list of the rank (or periodic image) owning j, so
      // keep it only on the side of the smaller tag (a particle touching its own periodic image:
      // the image with the lexicographically larger position).
      if (!newton_pair && j >= nlocal) {
        if (tag[i] > tag[j]) continue;
        if (tag[i] == tag[j]) {
          const double *xi = x[i], *xj = x[j];
          const bool larger = xj[0] != xi[0] ? xj[0] > xi[0] : xj[1] != xi[1] ? xj[1] > xi[1] : xj[2] > xi[2];
          if (!larger) continue;
        }
      }
      const int itype = type[i], jtype = type[j];
      if (itype > max_type || jtype > max_type)
        fail_on_this_rank(lmp, FLERR, me + ": atom type " + std::to_string(std::max(itype, jtype)) +
                                          " is not covered by the material table of the pair style (types up to " +
                                          std::to_string(max_type) + ")");
      // Evaluate from the side of the smaller tag, so the row does not depend on which atom's
      // list holds the pair (rank and binning invariant). The history slot is the list owner's
      // view; the other atom's view is its negation (as the contact-history fix stores it).
      const bool swap = tag[i] > tag[j];
      const int a = swap ? j : i, b = swap ? i : j;
      const double *stored = history ? history->slot(i, jj) : nullptr;
      for (int k = 0; k < nhist_; k++) hist[k] = swap ? -stored[k] : stored[k];
      const double hist_out[6] = {hist[0], hist[1], hist[2], hist[3], hist[4], hist[5]};
      const gran::SphereView sa{x[a], vel(a), omg(a), radius[a]};
      const gran::SphereView sb{x[b], vel(b), omg(b), radius[b]};
      // hist is a copy: even with history_update=false a model may rescale the spring it is given
      if (!law.evaluate(sa, sb, pair->effective_mass(a, b), table.at(type[a], type[b]), hist, false, dt, res)) continue;
      data_.push_back(double(tag[a]));
      data_.push_back(double(tag[b]));
      data_.push_back(res.delta);
      data_.push_back(res.Fn);
      for (int k = 0; k < 3; k++) data_.push_back(res.Ft[k]);
      for (int k = 0; k < nhist_; k++) data_.push_back(hist_out[k]);
    }
  }

  size_local_rows = int(data_.size() / ncols);
  rows_.resize(size_local_rows);
  for (int r = 0; r < size_local_rows; r++) rows_[r] = &data_[std::size_t(r) * ncols];
  array_local = size_local_rows ? rows_.data() : nullptr;
}

double ComputePairGranLocal::memory_usage()
{
  return double(data_.capacity() + ghost_vo_.capacity()) * sizeof(double) + double(rows_.capacity()) * sizeof(double *);
}

static void *create_compute_pair_gran_local(void *lmp, int narg, char **arg)
{
  return new ComputePairGranLocal(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_compute_pair_gran_local("compute", "pair/gran/local",
                                                 "per-contact output of the dembridge granular pair styles (never mutates history)",
                                                 create_compute_pair_gran_local);

}  // namespace dembridge
