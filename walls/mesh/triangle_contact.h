// Sphere-triangle closest point with LIGGGHTS 3.8's face/edge/corner rules
// (resolveTriSphereContactBary, spec liggghts-walls §4.4).
#pragma once

#include "triangle_mesh.h"

namespace dembridge::mesh {

enum class ContactKind : std::uint8_t { None, Face, Edge, Corner };

struct TriangleContact {
  double dist_minus_r;  // d - R; <= 0 means contact (non-strict, spec §2); 1e6 - R if none
  Vec3 delta;           // closest wall point - particle centre
  Vec3 bary;            // barycentric weights of the closest point (for the wall velocity)
  int sign;             // barycentric sign code 1..7 (7 = face)
  ContactKind kind;     // None when the closest feature is an inactive edge/corner
};

constexpr double kNoContactDistance = 1000000.0;

TriangleContact resolve_contact(const TriangleMesh &mesh, int t, const Vec3 &p, double radius);

}  // namespace dembridge::mesh
