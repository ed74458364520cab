#include "fix_check_timestep_gran.h"

#include "fix_mesh_surface.h"
#include "fix_property_global.h"
#include "fix_wall_gran.h"
#include "command_args.h"
#include "pair_gran.h"
#include "timestep_estimates.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "neighbor.h"
#include "style_registry.h"
#include "update.h"
#include "utils.h"

#include <cmath>
#include <cstdio>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace dembridge {

namespace {
constexpr double BIG = 1.0e6;  // LIGGGHTS's start value of the minima
}  // namespace

FixCheckTimestepGran::FixCheckTimestepGran(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  cmd_ = std::string("Fix check/timestep/gran (id ") + id + ")";
  CommandArgs a(lmp, cmd_, narg, arg, 3);
  if (std::strcmp(a.peek(), "check_every_time") == 0) a.word("check_every_time");
  nevery = a.integer("N");
  if (nevery <= 0) a.fail("N", "expected a positive number of steps, got " + std::to_string(nevery));
  limit_rayleigh_ = a.positive("fraction_rayleigh");
  limit_hertz_ = a.positive("fraction_hertz");
  while (!a.done()) {
    const std::string key = a.word("keyword");
    if (key == "warn") warn_ = a.yes_no("warn");
    else if (key == "error") error_ = a.yes_no("error");
    else if (key == "vmax") {
      vmax_user_ = a.number("vmax");
      if (vmax_user_ < 0.0) a.fail("vmax", "expected a speed >= 0, got " + std::string(arg[a.position() - 1]));
    } else
      a.fail("'" + key + "'", "unknown keyword (expected warn, error or vmax)");
  }
  vector_flag = 1;
  size_vector = 3;
  global_freq = nevery;
  extvector = 1;
}

int FixCheckTimestepGran::setmask() { return END_OF_STEP; }

void FixCheckTimestepGran::init()
{
  if (!atom->radius_flag || !atom->rmass_flag)
    error->all(FLERR, "Fix check/timestep/gran can only be used together with atom style sphere");
  if (!dynamic_cast<PairGran *>(force->pair))
    error->all(FLERR, cmd_ + ": needs a granular pair style of this plugin (pair_style gran ...)");
  const property::GlobalProperty *Y = FixPropertyGlobal::find(lmp, "youngsModulus");
  const property::GlobalProperty *nu = FixPropertyGlobal::find(lmp, "poissonsRatio");
  if (!Y || !nu)
    error->all(FLERR, "Fix check/timestep/gran only works with a pair style that defines youngsModulus and poissonsRatio");
  const int n = atom->ntypes;
  try {
    Y->require(property::Kind::PerType, n, cmd_);
    nu->require(property::Kind::PerType, n, cmd_);
  } catch (const std::exception &e) {
    error->all(FLERR, e.what());
  }
  Y_.assign(n + 1, 0.0);
  nu_.assign(n + 1, 0.0);
  for (int t = 1; t <= n; ++t) {
    Y_[t] = Y->per_type(t);
    nu_[t] = nu->per_type(t);
  }
}

// LIGGGHTS takes the moving meshes of the last mesh wall.
double FixCheckTimestepGran::mesh_speed_max()
{
  const FixWallGran *wall = nullptr;
  for (Fix *f : modify->get_fix_by_style("^wall/gran")) {
    auto *w = dynamic_cast<FixWallGran *>(f);
    if (w && w->is_mesh_wall()) wall = w;
  }
  double vmax_sqr = 0.0;
  if (!wall) return 0.0;
  for (const FixMeshSurface *m : wall->meshes()) {
    const mesh::TriangleMesh &tm = m->mesh();
    if (!m->moving() || !tm.has_velocity()) continue;
    for (int tri = 0; tri < tm.size(); ++tri)
      for (int node = 0; node < 3; ++node) {
        const mesh::Vec3 &v = tm.node_velocity(tri, node);
        vmax_sqr = std::max(vmax_sqr, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      }
  }
  return std::sqrt(vmax_sqr);
}

void FixCheckTimestepGran::estimate()
{
  const double *const *v = atom->v;
  const double *r = atom->radius;
  const double *m = atom->rmass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double tr = BIG, rmin = BIG, vmax_sqr = 0.0;
  for (int i = 0; i < nlocal; ++i) {
    if (!(mask[i] & groupbit)) continue;
    const double rho = gran::sphere_density(m[i], r[i]);
    tr = std::min(tr, gran::rayleigh_time(r[i], rho, Y_[type[i]], nu_[type[i]]));
    vmax_sqr = std::max(vmax_sqr, v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
    rmin = std::min(rmin, r[i]);
  }
  MPI_Allreduce(&tr, &rayleigh_time_, 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(&rmin, &r_min_, 1, MPI_DOUBLE, MPI_MIN, world);
  double vmax_all = 0.0;
  MPI_Allreduce(&vmax_sqr, &vmax_all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (vmax_user_ * vmax_user_ > vmax_all) vmax_all = vmax_user_ * vmax_user_;
  v_rel_ = gran::relative_speed(std::sqrt(vmax_all), mesh_speed_max());

  // The Hertz estimate: each particle against its twin of the same type.
  double th = 1000000.;
  if (v_rel_ != 0.0)
    for (int i = 0; i < nlocal; ++i) {
      if (!(mask[i] & groupbit)) continue;
      const int t = type[i];
      const double Yeff = gran::effective_modulus(Y_[t], nu_[t], Y_[t], nu_[t]);
      th = std::min(th, gran::hertz_time(r[i], gran::sphere_density(m[i], r[i]), Yeff, v_rel_));
    }
  MPI_Allreduce(&th, &hertz_time_, 1, MPI_DOUBLE, MPI_MIN, world);
}

void FixCheckTimestepGran::report(const std::string &msg)
{
  if (error_) error->all(FLERR, cmd_ + ": " + msg);
  error->warning(FLERR, msg);
}

void FixCheckTimestepGran::end_of_step()
{
  estimate();
  const double dt = update->dt, skin = neighbor->skin;
  fraction_[0] = dt / rayleigh_time_;
  fraction_[1] = dt / hertz_time_;
  fraction_[2] = (v_rel_ * dt) / skin;
  if (!(error_ || (warn_ && comm->me == 0))) return;
  char msg[512];
  if (fraction_[0] > limit_rayleigh_) {
    std::snprintf(msg, sizeof msg, "time-step is %f %% of rayleigh time", fraction_[0] * 100.);
    report(msg);
  }
  if (fraction_[1] > limit_hertz_) {
    std::snprintf(msg, sizeof msg, "time-step is %f %% of hertz time", fraction_[1] * 100.);
    report(msg);
  }
  if (fraction_[2] > 1) {
    std::snprintf(msg, sizeof msg,
                  "time step too large or skin too small - particles may relatively travel a distance of %f per "
                  "time-step, but skin is %f",
                  v_rel_ * dt, skin);
    report(msg);
  }
  if (v_rel_ * dt > r_min_)
    report("time step way too large - particles relativley move further than the minimum radius in one step");
}

double FixCheckTimestepGran::compute_vector(int n) { return (n >= 0 && n < 3) ? fraction_[n] : 0.0; }

static RegisterStyle reg_check_timestep("fix", "check/timestep/gran", "LIGGGHTS time-step check (Rayleigh, Hertz, skin)",
                                        create_fix<FixCheckTimestepGran>);

}  // namespace dembridge
