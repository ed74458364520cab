#include "body_inertia.h"

#include "math/inertia.h"

#include "atom.h"
#include "error.h"

namespace dembridge::state {

double **BodyInertia::rows() const
{
  if (name_.empty()) return nullptr;
  int flag = 0, cols = 0;
  const int ij = atom->find_custom(name_.c_str(), flag, cols);
  if (ij < 0 || flag != 1 || cols != 6)
    error->all(FLERR, cmd_ + ": inertia: '" + name_ + "' is not a per-atom d2_ property with 6 columns (define it "
                             "with fix property/atom d2_" + name_ + " 6 ghost yes and set Ixx Iyy Izz Ixy Ixz Iyz)");
  return atom->darray[ij];
}

BodyInertia::Tensor BodyInertia::tensor(int i, double mass) const
{
  if (double **J = rows()) return math::inertia_from_list(J[i]);
  return math::sphere_inertia(mass, atom->radius_flag ? atom->radius[i] : 0.0);
}

BodyInertia::Tensor BodyInertia::inverse(int i, double mass) const { return math::inverse_inertia(tensor(i, mass)); }

}  // namespace dembridge::state
