#include "body_inertia.h"

#include "equivalent_mass.h"

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
  if (double **J = rows()) {
    const double *r = J[i];
    return {r[0], r[3], r[4], r[3], r[1], r[5], r[4], r[5], r[2]};
  }
  const double J = atom->radius_flag ? 0.4 * mass * atom->radius[i] * atom->radius[i] : 0.0;
  return {J, 0, 0, 0, J, 0, 0, 0, J};
}

BodyInertia::Tensor BodyInertia::inverse(int i, double mass) const
{
  const Tensor J = tensor(i, mass);
  Tensor inv{};
  if (J[1] == 0.0 && J[2] == 0.0 && J[5] == 0.0) {  // principal axes (spheres): 1/J, no cofactor rounding
    for (int c = 0; c < 3; c++) inv[4 * c] = J[4 * c] > 0.0 ? 1.0 / J[4 * c] : 0.0;
    return inv;
  }
  const double det = J[0] * (J[4] * J[8] - J[5] * J[7]) - J[1] * (J[3] * J[8] - J[5] * J[6]) +
                     J[2] * (J[3] * J[7] - J[4] * J[6]);
  if (det > 0.0) inv = springs::parmec_inverse(J);
  return inv;
}

}  // namespace dembridge::state
