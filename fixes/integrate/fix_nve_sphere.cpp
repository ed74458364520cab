// fix nve/sphere: see fix_nve_sphere.h.
#include "fix_nve_sphere.h"
#include "sphere_fix_checks.h"
#include "sphere_verlet_kernel.h"
#include "style_registry.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "update.h"
#include "utils.h"

#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace dembridge {

FixNVESphereFlat::FixNVESphereFlat(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  cmd_ = std::string("fix ") + id + " " + style;
  dynamic_group_allow = 1;
  time_integrate = 1;
  if (narg > 3) inertia_ = integrate::disc_inertia(lmp, cmd_);  // the creator sends only nothing or 'disc' here
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, cmd_ + ": requires atom style sphere (per-atom radius, rmass, omega, torque)");
}

int FixNVESphereFlat::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE;
}

void FixNVESphereFlat::init()
{
  // the built-in takes run_style respa when it is set before the fix
  integrate::refuse_respa(lmp, cmd_, "run_style respa must come before the fix nve/sphere line (then LAMMPS's own fix runs it)");
  reset_dt();
  integrate::require_extended_particles(lmp, cmd_, groupbit);
}

void FixNVESphereFlat::reset_dt()
{
  dtv_ = update->dt;
  dtf_ = 0.5 * update->dt * force->ftm2v;
}

template <bool Drift> void FixNVESphereFlat::half_step()
{
  const int n = (igroup == atom->firstgroup) ? atom->nfirst : atom->nlocal;
  if (n <= 0) return;
  const integrate::SphereArrays a{atom->x[0], atom->v[0], atom->omega[0], atom->f[0], atom->torque[0],
                                  atom->radius, atom->rmass, atom->mask};
  static const bool avx2 = __builtin_cpu_supports("avx2");
  integrate::sphere_step<Drift>(a, {dtv_, dtf_, dtf_ / inertia_}, n, groupbit, avx2);
}

void FixNVESphereFlat::initial_integrate(int)
{
  half_step<true>();
}

void FixNVESphereFlat::final_integrate()
{
  half_step<false>();
}

// ---------------------------------------------------------------------------------------------
// Creator: the plain form (and 'disc') here, every other form to LAMMPS's own fix.

static FixFactory builtin_nve_sphere = nullptr;

static void *create_nve_sphere(void *lmp, int narg, char **arg)
{
  auto *l = static_cast<LAMMPS *>(lmp);
  const bool plain = narg == 3 || (narg == 4 && std::strcmp(arg[3], "disc") == 0);
  if (plain && !utils::strmatch(l->update->integrate_style, "^respa")) return new FixNVESphereFlat(l, narg, arg);
  if (!builtin_nve_sphere) l->error->all(FLERR, "fix nve/sphere: this LAMMPS has no built-in fix nve/sphere");
  return builtin_nve_sphere(lmp, narg, arg);
}

static RegisterStyle reg_nve_sphere("fix", "nve/sphere", "fix nve/sphere, bitwise the built-in (update dipole, respa: the built-in)",
                                    create_nve_sphere, &builtin_nve_sphere);

}  // namespace dembridge
