#include "rotation_check.h"

#include <cmath>
#include <cstdio>

namespace dembridge::mbdyn {

std::string rotation_matrix_defect(const std::array<double, 9>& R, double tol) {
  double biggest = 0, off = 0;
  for (double r : R) biggest = std::fmax(biggest, std::fabs(r));
  if (biggest == 0) return "is all zero";
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double d = (i == j) ? -1.0 : 0.0;
      for (int k = 0; k < 3; ++k) d += R[3 * k + i] * R[3 * k + j];
      off = std::fmax(off, std::fabs(d));
    }
  char buf[160];
  if (!(off <= tol)) {
    std::snprintf(buf, sizeof buf, "is not orthonormal: max |R^T R - I| = %.3g (tolerance %.3g)", off, tol);
    return buf;
  }
  const double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                     R[2] * (R[3] * R[7] - R[4] * R[6]);
  if (det < 0) {
    std::snprintf(buf, sizeof buf, "has determinant %.3g: a reflection, not a rotation", det);
    return buf;
  }
  return "";
}

}  // namespace dembridge::mbdyn
