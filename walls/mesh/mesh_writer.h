// Mesh output for ParaView: legacy VTK polydata (nodes, triangles; per triangle the normal, the
// mesh index and, when given, the force on it; per node the velocity) and ASCII STL. Several
// meshes go into one file.
#pragma once

#include "triangle_mesh.h"

#include <ostream>
#include <vector>

namespace dembridge::mesh {

struct MeshFrame {
  const TriangleMesh *mesh;
  std::vector<double> tri_force;  // 3 values per triangle, or empty
  const char *name;
};

void write_vtk(std::ostream &os, const std::vector<MeshFrame> &meshes, const char *title);
void write_stl(std::ostream &os, const std::vector<MeshFrame> &meshes);

}  // namespace dembridge::mesh
