#include "torsion_frame.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dembridge::torsion {

namespace {
constexpr double kOrthogonalityTolerance = 1e-8;  // on the dot product of the normalised directions

Vec3 unit(const Vec3& v, const char* name) {
  const double n = springs::norm(v);
  if (!(n > 0.0) || !std::isfinite(n))
    throw std::invalid_argument(std::string("TORSION_SPRING: ") + name + " must be a non-zero finite vector");
  return {v[0] / n, v[1] / n, v[2] / n};
}
}  // namespace

TorsionFrame reference_frame(const Vec3& zdir, const Vec3& xdir) {
  TorsionFrame f;
  f.z = unit(zdir, "zdir");
  f.x = unit(xdir, "xdir");
  const double c = springs::dot(f.z, f.x);
  if (std::fabs(c) > kOrthogonalityTolerance)
    throw std::invalid_argument("TORSION_SPRING: zdir and xdir must be orthogonal (normalised zdir.xdir = " +
                                std::to_string(c) + ")");
  f.y = springs::cross(f.z, f.x);
  return f;
}

TorsionFrame current_frame(const TorsionFrame& r, const Mat3& rot1) {
  return {apply(rot1, r.x), apply(rot1, r.y), apply(rot1, r.z)};
}

}  // namespace dembridge::torsion
