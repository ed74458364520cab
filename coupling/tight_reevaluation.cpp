#include "tight_reevaluation.h"

#include "atom.h"
#include "bond.h"
#include "comm.h"
#include "fix.h"
#include "force.h"
#include "modify.h"
#include "pair.h"
#include "update.h"

using namespace LAMMPS_NS;

namespace dembridge {

void reevaluate_forces_for_iterate(LAMMPS *lmp, const char *fix_id, int vflag,
                                   const std::function<void()> &before_fixes)
{
  Update *update = lmp->update;
  Atom *atom = lmp->atom;
  const int saved = update->setupflag;
  update->setupflag = 1;
  lmp->comm->forward_comm();
  const int nall = atom->nlocal + atom->nghost;
  double **f = atom->f;
  for (int i = 0; i < nall; ++i) f[i][0] = f[i][1] = f[i][2] = 0.0;
  if (atom->torque_flag)
    for (int i = 0; i < nall; ++i) atom->torque[i][0] = atom->torque[i][1] = atom->torque[i][2] = 0.0;
  Force *force = lmp->force;
  if (force->pair) force->pair->compute(0, 0);
  if (atom->molecular && force->bond) force->bond->compute(0, 0);
  if (force->newton) lmp->comm->reverse_comm();
  if (before_fixes) before_fixes();
  Modify *modify = lmp->modify;
  const int me = modify->find_fix(fix_id);
  for (int i = 0; i < me; ++i)
    if (modify->fmask[i] & FixConst::POST_FORCE) modify->fix[i]->post_force(vflag);
  update->setupflag = saved;
}

}  // namespace dembridge
