// Node identity for the mesh topology: nodes whose coordinates all differ by less than the mesh
// precision are the same node (LIGGGHTS nodesAreEqual, spec §4.1). Hash grid with cells of twice the precision, so a lookup visits 27 cells.
#pragma once

#include "triangle_mesh.h"

#include <array>
#include <vector>

namespace dembridge::mesh {

// ids[t][k] = node id of node k of triangle t; ids are dense, in order of first appearance.
std::vector<std::array<int, 3>> index_nodes(const std::vector<TriangleNodes> &tris, double precision);

}  // namespace dembridge::mesh
