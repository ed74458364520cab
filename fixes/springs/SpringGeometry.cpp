#include "SpringGeometry.h"

#include <stdexcept>
#include <string>

namespace dembridge::springs {

namespace {
Vec3 project_out(const Vec3& w, const Vec3& d) { return w - dot(w, d) * d; }
}  // namespace

SpringFrame spring_frame(DirectionMode mode, const Vec3& d, const SpringKinematics& kin) {
  SpringFrame f;
  const Vec3 w = kin.q - kin.p;
  f.distance = norm(w);
  switch (mode) {
    case DirectionMode::Follower:
      f.len = f.distance;
      if (f.len > 0.0) f.z = {w[0] / f.len, w[1] / f.len, w[2] / f.len};
      break;
    case DirectionMode::Constant:
      f.len = dot(w, d);
      f.z = d;  // fixed in space, not co-rotated even with part2 >= 0 (spec §2.1)
      break;
    case DirectionMode::Planar: {
      const Vec3 wp = project_out(w, d);
      f.len = norm(wp);
      if (f.len > 0.0) f.z = {wp[0] / f.len, wp[1] / f.len, wp[2] / f.len};
      break;
    }
    case DirectionMode::Plane:
      f.z = kin.normal;
      f.len = dot(kin.p - kin.q, kin.normal);  // signed distance of point1 from the plane
      break;
  }
  f.velocity = dot(f.z, kin.u);
  f.u_tangential = kin.u - f.velocity * f.z;
  return f;
}

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

Vec3 relative_velocity(const Vec3& v1, const Vec3& w1, const Vec3& a, bool has_part2, const Vec3& v2, const Vec3& w2,
                       const Vec3& b) {
  const Vec3 u1 = v1 + cross(w1, a);
  if (!has_part2) return Vec3{} - u1;
  return (v2 + cross(w2, b)) - u1;
}

Vec3 unit_direction(const Vec3& d, const char* what) {
  const double l = norm(d);
  if (!(l > 0.0) || !std::isfinite(l)) throw std::invalid_argument(std::string(what) + ": direction must be non-zero and finite");
  return {d[0] / l, d[1] / l, d[2] / l};
}

}  // namespace dembridge::springs
