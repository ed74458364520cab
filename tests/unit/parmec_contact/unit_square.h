// The unit square [0,1]² at height z as two triangles (normal +z): the surface the obstacle and MESH body
// tests place, move and touch.
#pragma once

#include <vector>

#include "triangle_mesh.h"

inline std::vector<dembridge::mesh::TriangleNodes> unit_square(double z)
{
  using dembridge::mesh::TriangleNodes;
  using dembridge::mesh::Vec3;
  return {TriangleNodes{Vec3{0, 0, z}, Vec3{1, 0, z}, Vec3{1, 1, z}}, TriangleNodes{Vec3{0, 0, z}, Vec3{1, 1, z}, Vec3{0, 1, z}}};
}
