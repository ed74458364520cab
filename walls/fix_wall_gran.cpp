#include "fix_wall_gran.h"
#include "rank_error.h"

#include "fix_property_global.h"
#include "style_registry.h"
#include "container_bytes.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {
constexpr int kMeshContactsPerAtom = 8;  // particle-triangle contacts one atom may have at a time
}

walls::WallSpec FixWallGran::parse(LAMMPS *lmp, int narg, char **arg)
{
  const std::string style = arg[2];
  try {
    return walls::parse_wall_gran(style, std::vector<std::string>(arg + 3, arg + narg), "fix " + std::string(arg[0]) + " " + style);
  } catch (const gran::SyntaxError &e) {
    lmp->error->all(FLERR, e.what());
  }
}

FixWallGran::FixWallGran(LAMMPS *lmp, int narg, char **arg) : FixWallGran(lmp, narg, arg, parse(lmp, narg, arg)) {}

FixWallGran::FixWallGran(LAMMPS *lmp, int narg, char **arg, walls::WallSpec spec) :
    PerAtomRecordsFix(lmp, narg, arg, 1 + spec.model.contact.history_size()), spec_(std::move(spec))
{
  const auto &c = spec_.model.contact;
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, cmd_ + ": requires atom style sphere (per-atom radius, rmass, omega, torque); use 'atom_style sphere'");
  if (c.cohesion != gran::CohesionModel::Off && domain->dimension == 2)
    error->all(FLERR, cmd_ + ": cohesion models are valid for 3d simulations only");
  if (c.rolling != gran::RollingModel::Off && domain->dimension == 2)
    error->all(FLERR, cmd_ + ": rolling friction is implemented for 3d simulations only");
  for (const auto &w : spec_.model.warnings)
    if (comm->me == 0) error->warning(FLERR, w);
  if (!spec_.is_mesh) check_wall_type(spec_.primitive.wall_type, "primitive type");
  law_ = gran::ContactLaw(c);
  capacity_ = spec_.is_mesh ? kMeshContactsPerAtom : 1;
  set_records_per_atom(capacity_);
}

int FixWallGran::setmask() { return FixConst::POST_FORCE; }

void FixWallGran::check_wall_type(int type, const char *what)
{
  if (type < 1 || type > atom->ntypes)
    error->all(FLERR, cmd_ + ": " + what + " " + std::to_string(type) + " is out of range: 1 <= type <= max type as defined in create_box (" +
                          std::to_string(atom->ntypes) + ")");
}

void FixWallGran::init()
{
  const std::string units = update->unit_style;
  if (units != "si" && units != "cgs" && units != "lj")
    error->all(FLERR, cmd_ + ": cannot use the non-consistent unit system '" + units + "'; use 'units si', 'cgs' or 'lj'");
  const auto unit_system = units == "si" ? gran::UnitSystem::SI : units == "cgs" ? gran::UnitSystem::CGS : gran::UnitSystem::LJ;
  // The wall type counts towards the table (spec §5): every type of create_box.
  try {
    table_ = gran::MaterialTable::build(
        spec_.model, [this](const std::string &name) { return FixPropertyGlobal::find(lmp, name); }, atom->ntypes, unit_system,
        force->nktv2p);
  } catch (const gran::MaterialError &e) {
    std::string m = e.what();
    const std::string pp = "pair_style " + spec_.model.style;
    if (m.compare(0, pp.size(), pp) == 0) m = cmd_ + m.substr(pp.size());
    error->all(FLERR, m);
  }
  init_meshes();
  fix_rigid_ = nullptr;  // the first rigid-body fix, as the pair styles
  for (Fix *f : modify->get_fix_list())
    if (f->rigid_flag) {
      fix_rigid_ = f;
      break;
    }
}

void FixWallGran::find_rigid_masses()
{
  rigid_body_ = nullptr;
  rigid_mass_ = nullptr;
  if (!fix_rigid_) return;
  int dim;
  rigid_body_ = static_cast<const int *>(fix_rigid_->extract("body", dim));
  rigid_mass_ = static_cast<const double *>(fix_rigid_->extract("masstotal", dim));
  if (!rigid_body_ || !rigid_mass_)
    error->all(FLERR, cmd_ + ": the rigid-body fix " + std::string(fix_rigid_->id) +
                          " does not provide body masses (extract 'body'/'masstotal')");
}

void FixWallGran::setup(int vflag) { post_force(vflag); }

void FixWallGran::post_force(int /*vflag*/)
{
  const bool update_history = !update->setupflag;  // spec §2: no shear update during run setup
  if (record_) contact_rows_.clear();
  find_rigid_masses();
  if (spec_.is_mesh) mesh_pass(update_history);
  else primitive_pass(update_history);
}

double FixWallGran::memory_usage()
{
  return PerAtomRecordsFix::memory_usage() + state::containers_bytes(contact_rows_, kept_, meshes_);
}

// One contact: the law, then f_i/torque_i (the increment summed first, spec §2). fpw returns the
// change of f_i (the mesh force is its negative, spec §8).
void FixWallGran::touch(int i, const gran::WallTouch &w, int wall_type, double *hist, bool update_history, int mesh, int element,
                        double *fpw)
{
  double **f = atom->f, **torque = atom->torque;
  if (walls::normal_undefined(w.delta, atom->radius[i])) undefined_normal(i, mesh, element);
  const gran::SphereView a{atom->x[i], atom->v[i], atom->omega[i], atom->radius[i], atom->rmass[i]};
  gran::ContactResult res;
  const double meff = (rigid_body_ && rigid_body_[i] >= 0) ? rigid_mass_[rigid_body_[i]] : atom->rmass[i];
  law_.evaluate_wall(a, w, meff, table_.at(atom->type[i], wall_type), hist, update_history, update->dt, res);
  for (int k = 0; k < 3; ++k) {
    const double before = f[i][k];
    f[i][k] += res.F[k];
    torque[i][k] += res.Ti[k];
    fpw[k] = f[i][k] - before;
  }
  if (record_) {
    WallContactRecord r{i, mesh, element, res.delta, res.Fn, {}, {}, {}, {}};
    for (int k = 0; k < history_size(); ++k) r.hist[k] = hist[k];
    for (int k = 0; k < 3; ++k) {
      r.F[k] = res.F[k];
      r.Ft[k] = res.Ft[k];
      r.cp[k] = atom->x[i][k] + w.delta[k];
    }
    contact_rows_.push_back(r);
  }
}

// The sphere's centre lies on the wall: no contact normal. Name the fix, the atom and the wall.
void FixWallGran::undefined_normal(int i, int mesh, int element)
{
  const double *x = atom->x[i];
  const std::string wall = mesh < 0 ? "the " + spec_.primitive.describe()
                                    : "triangle " + std::to_string(element + 1) + " (file order) of mesh " + spec_.mesh_ids[mesh];
  fail_on_this_rank(lmp, FLERR, cmd_ + ": atom " + std::to_string(atom->tag[i]) + " at (" +
                                    fmt::format("{:.17g} {:.17g} {:.17g}", x[0], x[1], x[2]) + ") has its centre on " + wall +
                                    " (closer than 1e-12 of its radius): the contact normal is undefined (LIGGGHTS 3.8 computes NaN "
                                    "forces here); move the atom off the wall");
}

void FixWallGran::primitive_pass(bool update_history)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  double **x = atom->x;
  const double *radius = atom->radius;
  const auto &wall = spec_.primitive;
  const double zero[3] = {0.0, 0.0, 0.0};
  double vshear[3], delta[3], fpw[3], scratch[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < nlocal; ++i) {
    if (!(mask[i] & groupbit)) continue;
    double dist_minus_r;
    const bool ok = wall.distance(x[i], radius[i], dist_minus_r, delta);
    if (!ok)
      fail_on_this_rank(lmp, FLERR, cmd_ + ": atom " + std::to_string(atom->tag[i]) +
                                        " lies on the cylinder axis; the wall normal is undefined (LIGGGHTS computes NaN forces here)");
    if (dist_minus_r > 0.0) {  // not touching: the history is cleared at once (spec §3)
      if (records_.count(i)) records_.remove(i, 0);
      continue;
    }
    double *hist = scratch;
    if (history_size() > 0) hist = 1 + (records_.count(i) ? records_.record(i, 0) : records_.append(i, 0.0));
    const double *vw = zero;
    if (spec_.shear_dim >= 0) {
      wall.shear_velocity(x[i], spec_.shear_dim, spec_.shear_v, vshear);
      vw = vshear;
    }
    touch(i, gran::WallTouch{dist_minus_r, delta, vw}, wall.wall_type, hist, update_history, -1, -1, fpw);
  }
}

// A restart file may not give an atom more contacts than this fix keeps (the mesh pass's slots).
void FixWallGran::check_restored(int i)
{
  if (records_.count(i) > capacity_)
    fail_on_this_rank(lmp, FLERR, cmd_ + ": the restart file holds " + std::to_string(records_.count(i)) + " wall contacts for atom " +
                                      std::to_string(atom->tag[i]) + ", more than this fix keeps (" + std::to_string(capacity_) + ")");
}

// ---------------------------------------------------------------------------------------------
// Creators: `fix wall/gran` with LAMMPS's own syntax goes to the built-in fix (bit for bit its
// numbers); the LIGGGHTS syntaxes to FixWallGran.

static FixFactory builtin_wall_gran = nullptr;

static void *create_wall_gran(void *lmp, int narg, char **arg)
{
  auto *l = static_cast<LAMMPS *>(lmp);
  const std::vector<std::string> args(arg + 3, arg + narg);
  if (narg > 3 && walls::is_lammps_wall_syntax(arg[2], args)) {
    if (!builtin_wall_gran)
      l->error->all(FLERR, "fix " + std::string(arg[0]) + " wall/gran: '" + args[0] +
                               "' is LAMMPS's own wall/gran syntax, but this LAMMPS has no built-in fix wall/gran (GRANULAR "
                               "package); use the LIGGGHTS syntax 'wall/gran model ...'");
    return builtin_wall_gran(lmp, narg, arg);
  }
  return new FixWallGran(l, narg, arg);
}

static void *create_wall_gran_legacy(void *lmp, int narg, char **arg) { return new FixWallGran(static_cast<LAMMPS *>(lmp), narg, arg); }

static RegisterStyle reg_wall_gran("fix", "wall/gran",
                                   "LIGGGHTS wall/gran model ... primitive|mesh (LAMMPS's own syntax goes to the built-in)",
                                   create_wall_gran, &builtin_wall_gran);
static RegisterStyle reg_w1("fix", "wall/gran/hooke", "LIGGGHTS 2.x wall, hooke without history", create_wall_gran_legacy);
static RegisterStyle reg_w2("fix", "wall/gran/hooke/history", "LIGGGHTS 2.x wall, hooke with shear history", create_wall_gran_legacy);
static RegisterStyle reg_w3("fix", "wall/gran/hertz/history", "LIGGGHTS 2.x wall, hertz with shear history", create_wall_gran_legacy);
static RegisterStyle reg_w4("fix", "wall/gran/hooke/stiffness", "LIGGGHTS 2.x wall, hooke/stiffness", create_wall_gran_legacy);
static RegisterStyle reg_w5("fix", "wall/gran/hooke/history/stiffness", "LIGGGHTS 2.x wall, hooke/stiffness with history",
                            create_wall_gran_legacy);
static RegisterStyle reg_w6("fix", "wall/gran/hertz/history/stiffness", "LIGGGHTS 2.x wall, hertz/stiffness with history",
                            create_wall_gran_legacy);

}  // namespace dembridge
