#include "pair_gran.h"
#include "rank_error.h"
#include "pair_gran_contacts.h"
#include "math/vec3.h"

#include "fix_contact_history.h"
#include "fix_property_global.h"
#include "style_registry.h"
#include "container_bytes.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;

namespace dembridge {

using gran::Dialect;
using gran::TangentialModel;

// One history fix per history-carrying pair (sub-)style: the first takes this ID, the k-th of a
// pair hybrid this ID with "_k". The ID is stable across runs and processes (restart files).
static const char *const kHistoryFixId = "DEMBRIDGE_CONTACT_HISTORY";
static const char *const kHistoryFixStyle = "dembridge/contact/history";

PairGran::PairGran(LAMMPS *lmp, const char *style_name) : Pair(lmp), style_name_(style_name)
{
  single_enable = 0;
  finitecutflag = 1;
  restartinfo = 1;
  centroidstressflag = CENTROID_NOTAVAIL;
}

PairGran::~PairGran()
{
  if (!history_id_.empty() && modify->get_fix_by_id(history_id_)) modify->delete_fix(history_id_);
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
  if (c.cohesion != gran::CohesionModel::Off && domain->dimension == 2)
    error->all(FLERR, p + "cohesion models are valid for 3d simulations only");
  if (c.rolling != gran::RollingModel::Off && domain->dimension == 2)
    error->all(FLERR, p + "rolling friction is implemented for 3d simulations only");
  for (const auto &w : model_.warnings)
    if (comm->me == 0) error->warning(FLERR, w);
  law_ = gran::ContactLaw(c);
  // LAMMPS's own gran styles never use the f.r virial; LIGGGHTS gran/hooke allows it.
  no_virial_fdotr_compute = (c.history_size() > 0 || model_.dialect == Dialect::LammpsNumeric) ? 1 : 0;
}

void PairGran::settings(int narg, char **arg)
{
  settings_args_.assign(arg, arg + narg);
  apply_settings(settings_args_);
  reserve_history_place();
}

void PairGran::coeff(int narg, char **arg)
{
  if (narg != 2)
    error->all(FLERR, "pair_coeff for " + style_name_ + ": expected 'pair_coeff * *' with no coefficients "
                      "(coefficients come from " +
                          std::string(model_.dialect == Dialect::LammpsNumeric ? "the pair_style arguments" : "fix property/global") +
                          "), got " + std::to_string(narg) + " arguments");
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
  if (model_.dialect != Dialect::LammpsNumeric && units != "si" && units != "cgs" && units != "lj")
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
  if (ghi == 0 || model_.dialect == Dialect::LammpsNumeric) return atom->ntypes;
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
  // particles that fixes will insert later (fix pour, fix deposit) count as dynamic
  for (Fix *f : modify->get_fix_list()) {
    for (int t = 1; t <= n; t++) {
      int dim = 0, itype = t;
      auto *r = static_cast<double *>(f->extract("radius", itype));
      if (r && dim == 0 && itype >= 0) dyn[t] = std::max(dyn[t], *r);
    }
  }
  maxrad_dynamic_.assign(n + 1, 0.0);
  maxrad_frozen_.assign(n + 1, 0.0);
  MPI_Allreduce(dyn.data(), maxrad_dynamic_.data(), n + 1, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(frz.data(), maxrad_frozen_.data(), n + 1, MPI_DOUBLE, MPI_MAX, world);
}

const property::GlobalProperty *PairGran::find_property(const std::string &name)
{
  const property::GlobalProperty *fix = FixPropertyGlobal::find(lmp, name);
  auto it = restart_properties_.find(name);
  if (it == restart_properties_.end()) return fix;
  if (!fix) return &it->second;
  if (!fix->same_values(it->second) && comm->me == 0)
    error->warning(FLERR, "pair_style " + style_name_ + ": fix property/global " + name +
                              " redefines the value stored in the restart file; using the new definition");
  restart_properties_.erase(it);  // the deck's definition wins from now on
  return fix;
}

// Fixes act in the order they were defined. A fix pour or evaporate defined after pair_style
// must see the history already converted to per-atom lists in pre_exchange, so the place is
// taken now (as LAMMPS's own granular styles do) by a placeholder replaced in place at init.
// (Whatever the order, the history fix also tolerates atoms changed before it runs.)
void PairGran::reserve_history_place()
{
  if (model_.contact.history_size() == 0 || !domain->box_exist) return;
  if (history_id_.empty()) history_id_ = free_history_id();
  if (!modify->get_fix_by_id(history_id_)) modify->add_fix(history_id_ + " all " + kHistoryFixStyle + " 0");
}

std::string PairGran::free_history_id() const
{
  std::string name = kHistoryFixId;
  for (int k = 2; modify->get_fix_by_id(name); k++) name = std::string(kHistoryFixId) + "_" + std::to_string(k);
  return name;
}

void PairGran::create_history_fix()
{
  const int nv = model_.contact.history_size();
  if (history_id_.empty()) history_id_ = free_history_id();
  Fix *f = modify->get_fix_by_id(history_id_);
  if (f && std::string(f->style) != kHistoryFixStyle)
    error->all(FLERR, "pair_style " + style_name_ + ": fix ID " + history_id_ + " is reserved for the contact history, but a fix " +
                          f->style + " uses it; rename that fix");
  // same ID and style: add_fix replaces the placeholder (or an old model's history) in place
  if (!f || static_cast<FixContactHistory *>(f)->nvalues() != nv)
    f = modify->add_fix(history_id_ + " all " + kHistoryFixStyle + " " + std::to_string(nv));
  history_ = static_cast<FixContactHistory *>(f);
}

void PairGran::init_style()
{
  check_requirements();
  read_probe_setting();  // DEMBRIDGE_PAIR_PROBE (pair_gran_probe.cpp)

  freeze_groupbit_ = 0;
  for (Fix *f : modify->get_fix_by_style("^freeze")) freeze_groupbit_ |= f->groupbit;
  fix_rigid_ = nullptr;  // the first rigid-body fix, as the LAMMPS built-ins do
  for (Fix *f : modify->get_fix_list())
    if (f->rigid_flag) {
      fix_rigid_ = f;
      break;
    }
  comm_forward = fix_rigid_ ? 1 : 0;
  compute_type_radii();

  const int max_type = max_type_present();
  const std::string units = update->unit_style;
  const auto unit_system = units == "si" ? gran::UnitSystem::SI : units == "cgs" ? gran::UnitSystem::CGS : gran::UnitSystem::LJ;
  try {
    table_ = gran::MaterialTable::build(
        model_, [this](const std::string &name) { return find_property(name); }, max_type, unit_system, force->nktv2p);
  } catch (const gran::MaterialError &e) {
    error->all(FLERR, e.what());
  }
  uniform_coeffs_ = table_.uniform();
  if (model_.contact.history_size() > 0) {
    create_history_fix();
  } else {
    if (!history_id_.empty() && modify->get_fix_by_id(history_id_)) modify->delete_fix(history_id_);
    history_id_.clear();
    history_ = nullptr;
  }
  // REQ_HISTORY would need LAMMPS's internal fix neigh/history; our fix keeps the history.
  neighbor->add_request(this, NeighConst::REQ_SIZE);
}

void PairGran::init_list(int id, NeighList *ptr)
{
  Pair::init_list(id, ptr);
  if (history_) history_->set_list(ptr);
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

// Effective mass with the fix freeze and fix rigid rules (spec §2).
double PairGran::effective_mass(int i, int j) const
{
  double mi = atom->rmass[i], mj = atom->rmass[j];
  if (fix_rigid_ && int(mass_rigid_.size()) > std::max(i, j)) {
    if (mass_rigid_[i] > 0.0) mi = mass_rigid_[i];
    if (mass_rigid_[j] > 0.0) mj = mass_rigid_[j];
  }
  double meff = mi * mj / (mi + mj);
  if (atom->mask[i] & freeze_groupbit_) meff = mj;
  if (atom->mask[j] & freeze_groupbit_) meff = mi;
  return meff;
}

gran::PairLoopData PairGran::loop_data() const
{
  gran::PairLoopData d;
  d.x = atom->x[0];
  d.v = atom->v[0];
  d.omega = atom->omega[0];
  d.radius = atom->radius;
  d.rmass = atom->rmass;
  d.type = atom->type;
  d.mask = atom->mask;
  d.mass_rigid = fix_rigid_ ? mass_rigid_.data() : nullptr;
  d.freeze_groupbit = freeze_groupbit_;
  d.nlocal = atom->nlocal;
  d.newton_pair = force->newton_pair;
  d.ilist = list->ilist;
  d.numneigh = list->numneigh;
  d.firstneigh = list->firstneigh;
  d.neighmask = NEIGHMASK;
  if (history_) {
    d.hist = history_->values();
    d.touch = history_->touch_flags();
    d.hist_first = history_->first_slots();
    d.nv = history_->nvalues();
  }
  d.history_update = !update->setupflag;
  d.clear_separated = !model_.contact.stale_springs_until_rebuild || neighbor->ago == 0;
  d.dt = update->dt;
  d.coeffs = &table_.at(0, 0);
  d.coeff_stride = table_.max_type() + 1;
  d.uniform_coeffs = uniform_coeffs_;
  d.max_type = table_.max_type();
  d.law = &law_;
  d.scan = forced_scan_;
  return d;
}

void PairGran::loop_failed(const gran::PairLoopError &e)
{
  if (e.kind == gran::PairLoopError::TypeAfterInit)
    fail_on_this_rank(lmp, FLERR, "pair_style " + style_name_ + ": atom type " + std::to_string(atom->type[e.i]) +
                                      " appeared after init; the material table only covers types up to " + std::to_string(table_.max_type()));
  degenerate_contact(e.i, e.j, e.kind == gran::PairLoopError::Coincident);
}

void PairGran::begin_contacts()
{
  if (history_ && !history_->list_valid())
    fail_on_this_rank(lmp, FLERR, "pair_style " + style_name_ + ": contact history is not aligned with the neighbour list (internal error)");
  // fix rigid: body masses of owned and ghost atoms, refreshed when the ghosts change
  if (fix_rigid_ && neighbor->ago == 0) update_rigid_masses();
}

void PairGran::end_contacts()
{
  if (history_) history_->mark_updated();
  if (vflag_fdotr) virial_fdotr_compute();
}

// The serial compute's sink: adds each contact to the atoms of f and torque (the probe's scratch arrays too).
struct PairGran::ForceSink {
  PairGran *pair;
  double *f, *torque;
  int nlocal, newton_pair;
  void operator()(int i, int j, int, int, const gran::ContactResult &res) const
  {
    // rows at 64-bit offsets, two elements at a time (math::add_into): with int indices 3 * i + k,
    // GCC sign-extended each element's index anew; the sums are the same
    math::add_into(f + 3 * std::ptrdiff_t(i), res.F);
    math::add_into(torque + 3 * std::ptrdiff_t(i), res.Ti);
    if (newton_pair || j < nlocal) {
      math::subtract_from(f + 3 * std::ptrdiff_t(j), res.F);
      math::add_into(torque + 3 * std::ptrdiff_t(j), res.Tj);
    }
    if (pair->evflag) {
      double **x = pair->atom->x;
      pair->ev_tally_xyz(i, j, nlocal, newton_pair, 0.0, 0.0, res.F[0], res.F[1], res.F[2], x[i][0] - x[j][0], x[i][1] - x[j][1],
                         x[i][2] - x[j][2]);
    }
  }
  // the AVX2 loop fetches atom j's rows a few pairs ahead (pair_gran_lanes.h)
  void prefetch(int j) const
  {
    __builtin_prefetch(f + 3 * std::size_t(j), 1);
    __builtin_prefetch(torque + 3 * std::size_t(j), 1);
  }
};

void PairGran::serial_contacts(double *f, double *torque)
{
  for_each_contact(0, list->inum, ForceSink{this, f, torque, atom->nlocal, force->newton_pair});
}

void PairGran::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  if (!model_.force_on) return;
  begin_contacts();
  if (list->inum == 0) return end_contacts();  // (no per-atom arrays to point at)
  if (update->ntimestep == probe_step_) probe_pair_loop();
  serial_contacts(atom->f[0], atom->torque[0]);
  end_contacts();
}

// A contact the law cannot evaluate: name both atoms and what is wrong, instead of NaN forces.
void PairGran::degenerate_contact(int i, int j, bool coincident)
{
  const double *xi = atom->x[i], *xj = atom->x[j];
  const std::string p = "pair_style " + style_name_ + ": " +
      fmt::format("atom {} at ({:.17g} {:.17g} {:.17g}) and atom {} at ({:.17g} {:.17g} {:.17g})", atom->tag[i], xi[0], xi[1],
                  xi[2], atom->tag[j], xj[0], xj[1], xj[2]);
  if (coincident)
    fail_on_this_rank(lmp, FLERR, p + " are coincident (centre distance below 1e-12 of the radius sum, or not finite): the contact "
                                      "normal is undefined; remove or move one of them (e.g. delete_atoms overlap)");
  fail_on_this_rank(lmp, FLERR, p + fmt::format(" have no finite effective mass (masses {} and {}); give them a positive mass", atom->rmass[i],
                                                atom->rmass[j]));
}

double PairGran::memory_usage()
{
  return Pair::memory_usage() + state::containers_bytes(mass_rigid_, maxrad_dynamic_, maxrad_frozen_);
}

void PairGran::update_rigid_masses()
{
  int dim;
  auto *body = static_cast<int *>(fix_rigid_->extract("body", dim));
  auto *masstotal = static_cast<double *>(fix_rigid_->extract("masstotal", dim));
  if (!body || !masstotal)
    error->all(FLERR, "pair_style " + style_name_ + ": the rigid-body fix " + std::string(fix_rigid_->id) +
                          " does not provide body masses (extract 'body'/'masstotal')");
  mass_rigid_.assign(atom->nmax, 0.0);
  for (int i = 0; i < atom->nlocal; i++) mass_rigid_[i] = body[i] >= 0 ? masstotal[body[i]] : 0.0;
  comm->forward_comm(this);
}

int PairGran::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  for (int k = 0; k < n; k++) buf[k] = mass_rigid_[list[k]];
  return n;
}

void PairGran::unpack_forward_comm(int n, int first, double *buf)
{
  for (int k = 0; k < n; k++) mass_rigid_[first + k] = buf[k];
}

// Restart: the settings words, then the material properties the model used (LIGGGHTS loses them).
// pair hybrid stores only the settings of its sub-styles (pair_coeff is given again after
// read_restart); a single style also restores its `pair_coeff * *`.
void PairGran::write_restart(FILE *fp)
{
  write_restart_settings(fp);
}

void PairGran::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) setflag[i][j] = 1;
}

void PairGran::write_restart_settings(FILE *fp)
{
  auto put_int = [fp](int v) { fwrite(&v, sizeof(int), 1, fp); };
  auto put_str = [&](const std::string &w) {
    put_int(int(w.size()) + 1);
    fwrite(w.c_str(), sizeof(char), w.size() + 1, fp);
  };
  put_int(int(settings_args_.size()));
  for (const auto &w : settings_args_) put_str(w);
  std::vector<const property::GlobalProperty *> props;
  for (const auto &name : table_.used_properties()) {
    const property::GlobalProperty *p = FixPropertyGlobal::find(lmp, name);
    if (!p) {
      auto it = restart_properties_.find(name);
      if (it != restart_properties_.end()) p = &it->second;
    }
    if (p) props.push_back(p);
  }
  put_int(int(props.size()));
  for (const auto *p : props) {
    put_str(p->name());
    put_int(int(p->style()));
    put_int(p->ncols());
    put_int(int(p->values().size()));
    fwrite(p->values().data(), sizeof(double), p->values().size(), fp);
  }
}

void PairGran::read_restart_settings(FILE *fp)
{
  const bool me0 = comm->me == 0;
  auto get_int = [&]() {
    int v = 0;
    if (me0) utils::sfread(FLERR, &v, sizeof(int), 1, fp, nullptr, error);
    MPI_Bcast(&v, 1, MPI_INT, 0, world);
    return v;
  };
  auto get_str = [&]() {
    const int len = get_int();
    std::vector<char> buf(len);
    if (me0) utils::sfread(FLERR, buf.data(), sizeof(char), len, fp, nullptr, error);
    MPI_Bcast(buf.data(), len, MPI_CHAR, 0, world);
    return std::string(buf.data());
  };
  std::vector<std::string> args(get_int());
  for (auto &w : args) w = get_str();
  const int nprops = get_int();
  restart_properties_.clear();
  for (int k = 0; k < nprops; k++) {
    const std::string name = get_str();
    const auto style = static_cast<property::Style>(get_int());
    const int ncols = get_int();
    std::vector<double> values(get_int());
    if (me0) utils::sfread(FLERR, values.data(), sizeof(double), values.size(), fp, nullptr, error);
    MPI_Bcast(values.data(), int(values.size()), MPI_DOUBLE, 0, world);
    restart_properties_.emplace(name, property::GlobalProperty::from_parts(name, style, ncols, values));
  }
  settings_args_ = args;
  apply_settings(args);
}

// One creator per style name: the name selects the model and the dialect.
template <const char *Name> static void *create_pair(void *lmp)
{
  return new PairGran(static_cast<LAMMPS *>(lmp), Name);
}

#define DEMBRIDGE_PAIR(var, name, info) \
  static constexpr char var[] = name;   \
  static RegisterStyle reg_##var("pair", var, info, create_pair<var>)

DEMBRIDGE_PAIR(kGranHooke, "gran/hooke", "LIGGGHTS-compatible hooke, no tangential history (also LAMMPS numeric syntax)");
DEMBRIDGE_PAIR(kGranHookeHistory, "gran/hooke/history", "LIGGGHTS-compatible hooke with shear history (also LAMMPS numeric syntax)");
DEMBRIDGE_PAIR(kGranHertzHistory, "gran/hertz/history", "LIGGGHTS-compatible hertz with shear history (also LAMMPS numeric syntax)");
DEMBRIDGE_PAIR(kGranHookeStiffness, "gran/hooke/stiffness", "LIGGGHTS-compatible hooke/stiffness, no history");
DEMBRIDGE_PAIR(kGranHookeHistoryStiffness, "gran/hooke/history/stiffness", "LIGGGHTS-compatible hooke/stiffness with shear history");
DEMBRIDGE_PAIR(kGranHertzHistoryStiffness, "gran/hertz/history/stiffness", "LIGGGHTS-compatible hertz/stiffness with shear history");
DEMBRIDGE_PAIR(kGranHookeHistorySimple, "gran/hooke/history/simple", "alias of gran/hooke/history/stiffness");
DEMBRIDGE_PAIR(kGranHertzHistorySimple, "gran/hertz/history/simple", "alias of gran/hertz/history/stiffness");
DEMBRIDGE_PAIR(kGran, "gran", "LIGGGHTS 3.x syntax: gran model M tangential T ...");

}  // namespace dembridge
