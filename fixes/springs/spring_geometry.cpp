#include "spring_geometry.h"

#include <stdexcept>
#include <string>

namespace dembridge::springs {

double reference_stroke0(DirectionMode mode, const Vec3& d, const Vec3& P1, const Vec3& P2) {
  const Vec3 w = P2 - P1;
  switch (mode) {
    case DirectionMode::Follower: return norm(w);
    case DirectionMode::Constant: return dot(w, d);
    case DirectionMode::Planar: return norm(project_out(w, d));
    case DirectionMode::Plane: return 0.0;
  }
  return 0.0;
}

Vec3 plane_anchor(const Vec3& P1, const Vec3& plane_point, const Vec3& n) { return P1 - dot(P1 - plane_point, n) * n; }

Vec3 unit_direction(const Vec3& d, const char* what) {
  const double l = norm(d);
  if (!(l > 0.0) || !std::isfinite(l)) throw std::invalid_argument(std::string(what) + ": direction must be non-zero and finite");
  return {d[0] / l, d[1] / l, d[2] / l};
}

}  // namespace dembridge::springs
