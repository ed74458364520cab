// STL input: ASCII (vertices parsed as doubles; facet normals ignored, spec liggghts-walls §4.1)
// and binary (little-endian; float vertices widened to double). Throws MeshError with the file
// name and, for ASCII, the line number of the problem.
#pragma once

#include "triangle_mesh.h"

#include <string>
#include <vector>

namespace dembridge::mesh {

std::vector<TriangleNodes> read_stl(const std::string &path);

// True if the bytes are a binary STL (84-byte header + 50 bytes per facet, sizes consistent).
bool looks_like_binary_stl(const std::string &bytes);

}  // namespace dembridge::mesh
