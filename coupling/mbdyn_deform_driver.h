// The mapped points of MBDyn's `external structural mapping` driving the vertices of a
// fix mesh/surface/stress mesh, which deforms (fix mbdyn ... mapping MESH-ID points M): each
// vertex follows the mapped point it sits on at t0, and the loads of the points are the wall
// contact forces on the triangles split among the corners with the contact point's barycentric
// weights. The geometry is walls/mesh/vertex_loads.h; doc/fix_mbdyn.md.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace dembridge {

class FixMeshSurface;

class MbdynDeformDriver {
 public:
  using V3 = std::array<double, 3>;

  // Finds the mesh fix, marks it as moving and has it keep the step's contacts; errors name the
  // caller and the argument.
  void attach(LAMMPS_NS::LAMMPS *lmp, const std::string &mesh_id, const std::string &caller);
  // At the t0 message: every vertex is matched to the one mapped point within tol of it. Returns
  // an error message naming the vertex (empty if all match); the same on every rank.
  std::string bind(const std::vector<V3> &points, double tol);
  // Every vertex at its point's position, with its point's velocity; geometry recomputed.
  void move_to(const std::vector<V3> &x, const std::vector<V3> &v);
  // Adds each point's share of the wall contact forces of this step to out6[6 j .. 6 j + 2]
  // (collective: every rank's contacts, in a canonical order).
  void loads(double *out6) const;
  // Before a tight trial evaluation: the mesh's force totals start again from zero.
  void restart_totals();

 private:
  LAMMPS_NS::LAMMPS *lmp_ = nullptr;
  FixMeshSurface *mesh_ = nullptr;
  std::vector<std::array<int, 3>> corners_;  // [triangle][corner] -> mapped point
  std::size_t points_ = 0;
};

}  // namespace dembridge
