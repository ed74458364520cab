// See sphere_fix_checks.h.
#include "sphere_fix_checks.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "update.h"
#include "utils.h"

using namespace LAMMPS_NS;

namespace dembridge::integrate {

double disc_inertia(LAMMPS *lmp, const std::string &cmd)
{
  if (lmp->domain->dimension != 2)
    lmp->error->all(FLERR, cmd + ": keyword 'disc' requires a 2d simulation (dimension 2), this one is 3d");
  return 0.5;
}

void refuse_respa(LAMMPS *lmp, const std::string &cmd, const std::string &what_to_do)
{
  if (utils::strmatch(lmp->update->integrate_style, "^respa")) lmp->error->all(FLERR, cmd + ": " + what_to_do);
}

void require_extended_particles(LAMMPS *lmp, const std::string &cmd, int groupbit)
{
  const Atom *atom = lmp->atom;
  for (int i = 0; i < atom->nlocal; i++)
    if ((atom->mask[i] & groupbit) && atom->radius[i] == 0.0)
      lmp->error->one(FLERR, fmt::format("{}: atom {} has radius 0; requires extended particles", cmd, atom->tag[i]));
}

}  // namespace dembridge::integrate
