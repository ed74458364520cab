#include "mesh_placement.h"

namespace dembridge::mesh {

void apply_placement(std::vector<TriangleNodes> &tris, const std::vector<PlacementOp> &ops)
{
  for (const PlacementOp &op : ops) {
    if (op.kind == PlacementOp::Rotate && !(norm(op.v) > 0.0)) throw MeshError("rotate axis must not be zero");
    Quat q{1.0, 0.0, 0.0, 0.0};
    if (op.kind == PlacementOp::Rotate) {
      const double phi = op.s * 3.14159265 / 180.0;  // LIGGGHTS's truncated pi (quirk §10.8)
      q = axis_angle_quat(div_by(op.v, norm(op.v)), phi);
    }
    for (auto &nd : tris)
      for (auto &p : nd) {
        if (op.kind == PlacementOp::Move) p = add(p, op.v);
        else if (op.kind == PlacementOp::Scale) p = scale(p, op.s);
        else p = quat_rotate(p, q);
      }
  }
}

}  // namespace dembridge::mesh
