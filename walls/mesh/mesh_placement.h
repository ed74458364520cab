// fix mesh/surface 'move', 'scale', 'rotate' applied to the nodes in command-line order
// (spec liggghts-walls §4.1), including the LIGGGHTS angle conversion with pi = 3.14159265.
#pragma once

#include "triangle_mesh.h"

#include <vector>

namespace dembridge::mesh {

struct PlacementOp {
  enum Kind { Move, Scale, Rotate } kind;
  Vec3 v{0.0, 0.0, 0.0};  // move: displacement; rotate: axis
  double s = 0.0;         // scale: factor; rotate: angle in degrees
};

void apply_placement(std::vector<TriangleNodes> &tris, const std::vector<PlacementOp> &ops);

}  // namespace dembridge::mesh
