// A mesh whose vertices are driven point by point (fix mbdyn ... mapping MESH-ID): which driving
// point each triangle corner is, the triangles placed from the points, and the wall contact forces
// on the triangles distributed to the points with the contact point's barycentric weights, so the
// points' loads sum to the mesh force and their moments to the mesh moment (doc/fix_mbdyn.md).
#pragma once

#include "triangle_mesh.h"

#include <array>
#include <vector>

namespace dembridge::mesh {

using CornerPoints = std::vector<std::array<int, 3>>;  // [triangle][corner] -> driving point index

// Each corner of the mesh as it is now is matched to the one point within tol of it. Throws
// MeshError naming the triangle and corner (1-based) when no point or two points are that close.
CornerPoints match_corners(const TriangleMesh &m, const std::vector<Vec3> &points, double tol);

// The triangles with every corner at its point.
std::vector<TriangleNodes> nodes_from_points(const CornerPoints &map, const std::vector<Vec3> &points);

// Barycentric weights of p (a point on triangle t, e.g. a contact point) in the current mesh.
Vec3 barycentric(const TriangleMesh &m, int t, const Vec3 &p);

// One wall contact's force on the mesh: triangle, force, contact point (7 doubles, this layout).
struct MeshContact {
  double tri, f[3], cp[3];
};

// Adds each contact's force to the points of its triangle's corners (out: 3 per point), weighted
// by the contact point's barycentric weights (the last corner gets f minus the other two, so the
// three parts sum to f). The contacts are taken in a canonical order (sorted by their values), so
// the result does not depend on how they were split among ranks; the n contacts are left as they are.
void distribute_contacts(const TriangleMesh &m, const CornerPoints &map, const MeshContact *contacts, std::size_t n,
                         double *out);

}  // namespace dembridge::mesh
