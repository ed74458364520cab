// Mesh output for ParaView: legacy VTK polydata (nodes, triangles, per-triangle normal, node
// velocity magnitude and, when given, the force on each triangle) and ASCII STL.
#pragma once

#include "triangle_mesh.h"

#include <ostream>
#include <vector>

namespace dembridge::mesh {

// tri_force: 3 values per triangle, or empty.
void write_vtk(std::ostream &os, const TriangleMesh &m, const std::vector<double> &tri_force, const char *title);
void write_stl(std::ostream &os, const TriangleMesh &m, const char *solid_name);

}  // namespace dembridge::mesh
