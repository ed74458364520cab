// fix move/mesh: moves a fix mesh/surface (doc/fix_move_mesh.md, spec liggghts-walls §7.2).
// Several move/mesh fixes on one mesh superpose in fix order; the first one zeroes the node
// velocities each step. The motion itself is walls/mesh/mesh_movers.h.
#pragma once

#include "fix.h"

#include "mesh_movers.h"

#include <memory>
#include <string>

namespace dembridge {

class FixMeshSurface;

class FixMoveMesh : public LAMMPS_NS::Fix {
 public:
  FixMoveMesh(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void initial_integrate(int) override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

  const std::string &mesh_id() const { return mesh_id_; }

 private:
  std::string mesh_id_;
  std::string kind_;
  std::unique_ptr<mesh::MeshMover> mover_;
  mesh::LinearMover *linear_ = nullptr;  // linear/variable: velocity from variables
  mesh::RotateMover *rotate_ = nullptr;  // rotate/variable: omega from a variable
  std::string var_[3];
  int ivar_[3] = {-1, -1, -1};
  int nvar_ = 0;
  FixMeshSurface *mesh_ = nullptr;
  double time_ = 0.0;  // total time of this mover (kept in the restart file)

  void parse_mover(class MeshArgs &a);
};

}  // namespace dembridge
