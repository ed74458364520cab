// fix mesh/dump: writes meshes for ParaView every N steps (doc/fix_mesh_surface.md, "Output").
//   fix ID group mesh/dump N vtk|stl FILE MESHID [MESHID ...]
// FILE may contain '*' (replaced by the timestep, one file per frame). The LIGGGHTS lines
// `dump ID group mesh/stl|mesh/vtk ...` are dump styles of their own (dump_mesh.h); both write
// through mesh_output.h.
#pragma once

#include "mesh_output.h"

#include "fix.h"

namespace dembridge {

class FixMeshDump : public LAMMPS_NS::Fix {
 public:
  FixMeshDump(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void setup(int) override { write(); }
  void end_of_step() override { write(); }

 private:
  MeshOutput out_;
  void write();
};

}  // namespace dembridge
