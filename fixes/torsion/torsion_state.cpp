#include "torsion_state.h"

namespace dembridge::torsion {

void TorsionState::pack(double* b) const {
  const Vec3* v[5] = {&angle, &torque_total, &torque_spring, &xdir, &zdir};
  for (int k = 0; k < 5; ++k)
    for (int i = 0; i < 3; ++i) b[3 * k + i] = (*v[k])[i];
  b[15] = 0.0;  // reserved: keeps the record size stable for later fields
}

void TorsionState::unpack(const double* b) {
  Vec3* v[5] = {&angle, &torque_total, &torque_spring, &xdir, &zdir};
  for (int k = 0; k < 5; ++k)
    for (int i = 0; i < 3; ++i) (*v[k])[i] = b[3 * k + i];
}

}  // namespace dembridge::torsion
