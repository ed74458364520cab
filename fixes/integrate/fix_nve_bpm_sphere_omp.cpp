// fix nve/bpm/sphere/omp: see fix_nve_bpm_sphere_omp.h.
#include "fix_nve_bpm_sphere_omp.h"
#include "lammps_math_extra.h"
#include "sphere_fix_checks.h"
#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "update.h"
#include "utils.h"

#include <algorithm>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace dembridge {

FixNVEBPMSphereOMP::FixNVEBPMSphereOMP(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  cmd_ = std::string("fix ") + style;
  dynamic_group_allow = 1;
  time_integrate = 1;
  // the built-in's one keyword; anything else is an error naming it
  for (int iarg = 3; iarg < narg; iarg++) {
    if (std::strcmp(arg[iarg], "disc") == 0) {
      inertia_ = integrate::disc_inertia(lmp, cmd_);
    } else {
      error->all(FLERR, cmd_ + ": unknown keyword '" + arg[iarg] + "' (expected: 'disc' or nothing)");
    }
  }
  if (!atom->quat_flag || !atom->radius_flag || !atom->omega_flag)
    error->all(FLERR, cmd_ + ": requires atom style bpm/sphere (per-atom quat, radius and omega)");
}

int FixNVEBPMSphereOMP::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE;
}

void FixNVEBPMSphereOMP::init()
{
  // refused, not ignored
  integrate::refuse_respa(lmp, cmd_, "run_style respa is not supported (use fix nve/bpm/sphere without the /omp suffix)");
  reset_dt();
  integrate::require_extended_particles(lmp, cmd_, groupbit);
}

void FixNVEBPMSphereOMP::reset_dt()
{
  dtv_ = update->dt;
  dtf_ = 0.5 * update->dt * force->ftm2v;
}

int FixNVEBPMSphereOMP::threads() const
{
#if defined(_OPENMP)
  return std::max(1, comm->nthreads);  // `package omp N`, -pk omp N (-sf omp alone: OMP_NUM_THREADS)
#else
  return 1;
#endif
}

void FixNVEBPMSphereOMP::setup(int)
{
  const int n = threads();
  if (n > 1 && comm->me == 0) utils::logmesg(lmp, "{}: integration on {} OpenMP threads\n", cmd_, n);
#if !defined(_OPENMP)
  if (comm->nthreads > 1 && comm->me == 0)
    error->warning(FLERR, cmd_ + ": the dembridge plugin was built without OpenMP; using 1 thread");
#endif
}

// The arrays and constants of one integration step, copied out of Atom and the fix once: an opaque call in the
// loop (the quaternion routine) then cannot make the compiler load them again for every atom.
struct FixNVEBPMSphereOMP::Step {
  double *const *x, *const *v, *const *omega, *const *quat;
  const double *const *f, *const *torque;
  const double *radius, *rmass;
  double dtv, dtf, inertia;

  // Half a step of v and omega of atom i (the built-in's expressions, in its order).
  void kick(int i) const
  {
    const double dtfm = dtf / rmass[i];
    for (int c = 0; c < 3; c++) v[i][c] += dtfm * f[i][c];
    const double dtirotate = dtf / (inertia * (radius[i] * radius[i] * rmass[i]));
    for (int c = 0; c < 3; c++) omega[i][c] += dtirotate * torque[i][c];
  }
};

FixNVEBPMSphereOMP::Step FixNVEBPMSphereOMP::step() const
{
  return {atom->x, atom->v, atom->omega, atom->quat, atom->f, atom->torque, atom->radius, atom->rmass,
          dtv_, dtf_, inertia_};
}

// per(i) for every atom of the group, on the threads (each atom on its own: the split does not matter).
template <class Per> void FixNVEBPMSphereOMP::each_atom(Per per) const
{
  const int *const mask = atom->mask;
  const int nlocal = (igroup == atom->firstgroup) ? atom->nfirst : atom->nlocal;
  const int bit = groupbit;
  [[maybe_unused]] const int nthreads = threads();
#if defined(_OPENMP)
#pragma omp parallel for num_threads(nthreads) schedule(static) if (nthreads > 1) firstprivate(per)
#endif
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & bit) per(i);
}

// First half step: v and omega by half a step, x by a full step, the quaternion by the new omega. (The
// built-in updates x before omega; the two do not depend on each other, so the numbers are the same.)
void FixNVEBPMSphereOMP::initial_integrate(int)
{
  const Step s = step();
  const double dtq = 0.5 * s.dtv;
  each_atom([s, dtq](int i) {
    s.kick(i);
    for (int c = 0; c < 3; c++) s.x[i][c] += s.dtv * s.v[i][c];
    MathExtra::richardson_sphere(s.quat[i], s.omega[i], dtq);
  });
}

// Second half step: v and omega by half a step.
void FixNVEBPMSphereOMP::final_integrate()
{
  const Step s = step();
  each_atom([s](int i) { s.kick(i); });
}

static RegisterStyle reg_fix_nve_bpm_sphere_omp("fix", "nve/bpm/sphere/omp",
                                                "nve/bpm/sphere on the OpenMP threads of package omp, bitwise the built-in",
                                                create_fix<FixNVEBPMSphereOMP>);

}  // namespace dembridge
