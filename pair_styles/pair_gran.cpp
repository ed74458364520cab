#include "pair_gran.h"

#include "fix_property_global.h"
#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;

namespace dembridge {

using gran::Dialect;
using gran::TangentialModel;

PairGran::PairGran(LAMMPS *lmp, const char *style_name) : Pair(lmp), style_name_(style_name)
{
  single_enable = 0;
  finitecutflag = 1;
  restartinfo = 1;
  centroidstressflag = CENTROID_NOTAVAIL;
}

PairGran::~PairGran()
{
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

void PairGran::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) setflag[i][j] = 0;
}

void PairGran::apply_settings(const std::vector<std::string> &args)
{
  try {
    model_ = gran::parse_pair_style(style_name_, args);
  } catch (const gran::SyntaxError &e) {
    error->all(FLERR, e.what());
  }
  const auto &c = model_.contact;
  const std::string p = "pair_style " + style_name_ + ": ";
  // Sub-models that later issues add: refuse loudly rather than compute something else.
  if (model_.dialect == Dialect::LammpsNumeric)
    error->all(FLERR, p + "the LAMMPS numeric syntax (Kn Kt gamma_n gamma_t xmu dampflag) is not available yet in dembridge; "
                      "use the LIGGGHTS syntax with fix property/global, or run without the plugin");
  if (c.tangential == TangentialModel::History)
    error->all(FLERR, p + "tangential history styles are not available yet in dembridge");
  if (c.rolling != gran::RollingModel::Off) error->all(FLERR, p + "rolling_friction is not available yet in dembridge");
  if (c.cohesion != gran::CohesionModel::Off) error->all(FLERR, p + "cohesion is not available yet in dembridge");
  if (c.viscous) error->all(FLERR, p + "viscous is not available yet in dembridge");
  for (const auto &w : model_.warnings)
    if (comm->me == 0) error->warning(FLERR, w);
  law_ = gran::ContactLaw(c);
  no_virial_fdotr_compute = model_.contact.history_size() > 0 ? 1 : 0;
}

void PairGran::settings(int narg, char **arg)
{
  settings_args_.assign(arg, arg + narg);
  apply_settings(settings_args_);
}

void PairGran::coeff(int narg, char **arg)
{
  if (narg != 2)
    error->all(FLERR, "pair_coeff for " + style_name_ + ": expected 'pair_coeff * *' with no coefficients "
                      "(coefficients come from fix property/global), got " + std::to_string(narg) + " arguments");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
  for (int i = ilo; i <= ihi; i++)
    for (int j = std::max(jlo, i); j <= jhi; j++) setflag[i][j] = 1;
}

void PairGran::check_requirements()
{
  const std::string p = "pair_style " + style_name_ + ": ";
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, p + "requires atom style sphere (per-atom radius, rmass, omega, torque); use 'atom_style sphere'");
  if (!comm->ghost_velocity)
    error->all(FLERR, p + "requires ghost atoms to store velocity; add 'comm_modify vel yes'");
  const std::string units = update->unit_style;
  if (units != "si" && units != "cgs" && units != "lj")
    error->all(FLERR, p + "cannot use the non-consistent unit system '" + units + "'; use 'units si', 'cgs' or 'lj'");
  if (model_.contact.history_size() > 0 && force->newton_pair)
    error->all(FLERR, p + "contact history requires 'newton off' (newton pair off)");
  if (neighbor->delay != 0 && comm->me == 0)
    error->warning(FLERR, p + "it is heavily recommended to use 'neigh_modify delay 0' with granular pair styles");
}

int PairGran::max_type_present()
{
  int lo = atom->ntypes + 1, hi = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    lo = std::min(lo, atom->type[i]);
    hi = std::max(hi, atom->type[i]);
  }
  int glo, ghi;
  MPI_Allreduce(&lo, &glo, 1, MPI_INT, MPI_MIN, world);
  MPI_Allreduce(&hi, &ghi, 1, MPI_INT, MPI_MAX, world);
  if (ghi == 0) return atom->ntypes;  // no atoms yet: tables for every declared type
  if (glo != 1)
    error->all(FLERR, "pair_style " + style_name_ + ": atom types must start from 1 for granular simulations, but the smallest type present is " +
                          std::to_string(glo));
  return ghi;
}

void PairGran::compute_type_radii()
{
  const int n = atom->ntypes;
  std::vector<double> dyn(n + 1, 0.0), frz(n + 1, 0.0);
  for (int i = 0; i < atom->nlocal; i++) {
    auto &v = (atom->mask[i] & freeze_groupbit_) ? frz : dyn;
    v[atom->type[i]] = std::max(v[atom->type[i]], atom->radius[i]);
  }
  maxrad_dynamic_.assign(n + 1, 0.0);
  maxrad_frozen_.assign(n + 1, 0.0);
  MPI_Allreduce(dyn.data(), maxrad_dynamic_.data(), n + 1, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(frz.data(), maxrad_frozen_.data(), n + 1, MPI_DOUBLE, MPI_MAX, world);
}

void PairGran::init_style()
{
  check_requirements();

  freeze_groupbit_ = 0;
  for (Fix *f : modify->get_fix_by_style("^freeze")) freeze_groupbit_ |= f->groupbit;
  compute_type_radii();

  const int max_type = max_type_present();
  const std::string units = update->unit_style;
  const auto unit_system = units == "si" ? gran::UnitSystem::SI : units == "cgs" ? gran::UnitSystem::CGS : gran::UnitSystem::LJ;
  try {
    table_ = gran::MaterialTable::build(
        model_, [this](const std::string &name) { return FixPropertyGlobal::find(lmp, name); }, max_type, unit_system);
  } catch (const gran::MaterialError &e) {
    error->all(FLERR, e.what());
  }
  neighbor->add_request(this, NeighConst::REQ_SIZE);
}

double PairGran::init_one(int i, int j)
{
  if (setflag[i][j] == 0 && setflag[j][i] == 0)
    error->all(FLERR, "pair_style " + style_name_ + ": all pair coeffs are not set; use 'pair_coeff * *'");
  // Frozen-frozen pairs never interact, so they do not enlarge the cutoff (spec §2).
  const double dd = maxrad_dynamic_[i] + maxrad_dynamic_[j];
  const double fd = maxrad_frozen_[i] + maxrad_dynamic_[j];
  const double df = maxrad_dynamic_[i] + maxrad_frozen_[j];
  return std::max(dd, std::max(fd, df));
}

void PairGran::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  if (!model_.force_on) return;

  double **x = atom->x, **v = atom->v, **f = atom->f;
  double **omega = atom->omega, **torque = atom->torque;
  const double *radius = atom->radius, *rmass = atom->rmass;
  const int *type = atom->type, *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  const double dt = update->dt;
  const bool history_update = !update->setupflag;
  const int max_type = table_.max_type();

  const int inum = list->inum;
  const int *ilist = list->ilist, *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;

  gran::ContactResult res;
  double no_history[6] = {0, 0, 0, 0, 0, 0};  // history styles are rejected in settings() until they land
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const int itype = type[i];
    if (itype > max_type)
      error->one(FLERR, "pair_style " + style_name_ + ": atom type " + std::to_string(itype) +
                            " appeared after init; the material table only covers types up to " + std::to_string(max_type));
    const gran::SphereView a{x[i], v[i], omega[i], radius[i]};
    const bool ifrozen = mask[i] & freeze_groupbit_;
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const gran::SphereView b{x[j], v[j], omega[j], radius[j]};
      // effective mass with the fix freeze rule (spec §2)
      double meff = rmass[i] * rmass[j] / (rmass[i] + rmass[j]);
      if (ifrozen) meff = rmass[j];
      if (mask[j] & freeze_groupbit_) meff = rmass[i];
      if (!law_.evaluate(a, b, meff, table_.at(itype, type[j]), no_history, history_update, dt, res)) continue;
      for (int k = 0; k < 3; k++) {
        f[i][k] += res.F[k];
        torque[i][k] += res.Ti[k];
      }
      if (newton_pair || j < nlocal) {
        for (int k = 0; k < 3; k++) {
          f[j][k] -= res.F[k];
          torque[j][k] += res.Tj[k];
        }
      }
      if (evflag)
        ev_tally_xyz(i, j, nlocal, newton_pair, 0.0, 0.0, res.F[0], res.F[1], res.F[2], x[i][0] - x[j][0], x[i][1] - x[j][1],
                     x[i][2] - x[j][2]);
    }
  }
  if (vflag_fdotr) virial_fdotr_compute();
}

// Restart: the settings words; coefficients come from fix property/global.
void PairGran::write_restart(FILE *fp)
{
  const int n = settings_args_.size();
  fwrite(&n, sizeof(int), 1, fp);
  for (const auto &w : settings_args_) {
    const int len = w.size() + 1;
    fwrite(&len, sizeof(int), 1, fp);
    fwrite(w.c_str(), sizeof(char), len, fp);
  }
}

void PairGran::read_restart(FILE *fp)
{
  int n = 0;
  if (comm->me == 0) utils::sfread(FLERR, &n, sizeof(int), 1, fp, nullptr, error);
  MPI_Bcast(&n, 1, MPI_INT, 0, world);
  std::vector<std::string> args;
  for (int k = 0; k < n; k++) {
    int len = 0;
    if (comm->me == 0) utils::sfread(FLERR, &len, sizeof(int), 1, fp, nullptr, error);
    MPI_Bcast(&len, 1, MPI_INT, 0, world);
    std::vector<char> buf(len);
    if (comm->me == 0) utils::sfread(FLERR, buf.data(), sizeof(char), len, fp, nullptr, error);
    MPI_Bcast(buf.data(), len, MPI_CHAR, 0, world);
    args.emplace_back(buf.data());
  }
  settings_args_ = args;
  apply_settings(args);
  allocate();
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) setflag[i][j] = 1;
}

// One creator per style name: the name selects the dialect and defaults.
template <const char *Name> static void *create_pair(void *lmp)
{
  return new PairGran(static_cast<LAMMPS *>(lmp), Name);
}

static constexpr char kGranHooke[] = "gran/hooke";
static RegisterStyle reg_gran_hooke("pair", kGranHooke, "LIGGGHTS-compatible hooke, no tangential history",
                                    create_pair<kGranHooke>);

}  // namespace dembridge
