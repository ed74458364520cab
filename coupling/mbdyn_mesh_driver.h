// One MBDyn point driving the STL mesh of a fix mesh/surface/stress (fix mbdyn ... node mesh ID):
// the mesh follows the point's pose rigidly, its node velocities are v + w x (node - x), and the
// loads are the force and moment of the wall contacts on the mesh about the point (the totals of
// fix mesh/surface/stress, moved from its reference point to the point). doc/fix_mbdyn.md.
#pragma once

#include <array>
#include <string>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace dembridge {

class FixMeshSurface;

class MbdynMeshDriver {
 public:
  using V3 = std::array<double, 3>;
  using M9 = std::array<double, 9>;  // row-major, local to global

  // Finds the mesh fix and marks its mesh as moving; errors name the caller and the argument.
  void attach(LAMMPS_NS::LAMMPS *lmp, const std::string &mesh_id, const std::string &caller);
  // At the t0 message: the mesh is where MBDyn's point is at t0 (pose x0, R0).
  void bind(const V3 &x0, const M9 &R0);
  // Moves the mesh rigidly from its current pose to (x, R) and sets the node velocities.
  void move_to(const V3 &x, const M9 &R, const V3 &v, const V3 &w);
  // Force and moment about x of the wall contacts on the mesh, summed over ranks (collective).
  void loads(const V3 &x, double *out6) const;
  // Before a tight trial evaluation: the mesh's force totals start again from zero.
  void restart_totals();
  // Where the point bound to the mesh at t0 is now (for the pose check of the tests).
  V3 tracked_point() const;

 private:
  FixMeshSurface *mesh_ = nullptr;
  V3 x_{};
  M9 R_{1, 0, 0, 0, 1, 0, 0, 0, 1};
  int point_ = -1;  // the point attached to the mesh at x0
};

}  // namespace dembridge
