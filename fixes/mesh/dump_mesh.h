// dump mesh/stl and dump mesh/vtk: LIGGGHTS 3.8's mesh output lines as real LAMMPS dump styles
// (doc/fix_mesh_surface.md, "Output"), so a LIGGGHTS deck's dump lines run unchanged:
//   dump ID group mesh/stl N FILE [local|all] [binary] [MESHID ...]
//   dump ID group mesh/vtk N FILE [output face] KEYWORD ... [MESHID ...]
// Without mesh IDs: every fix mesh/surface(/stress) defined before the dump. Keywords and mesh
// IDs in any order. The files are written by mesh_output.h, as those of fix mesh/dump.
#pragma once

#include "lammps_dump_base.h"
#include "mesh_output.h"

namespace dembridge {

class MeshArgs;

class DumpMesh : public LAMMPS_NS::Dump {
 public:
  DumpMesh(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  void write() override;  // the whole frame: the base class's per-atom machinery is not used

 protected:
  void init_style() override;
  void write_header(LAMMPS_NS::bigint) override {}
  void pack(LAMMPS_NS::tagint *) override {}
  void write_data(int, double *) override {}

 private:
  MeshOutput out_;
  bool stl_keyword(MeshArgs &a, const std::string &w);
  bool vtk_keyword(MeshArgs &a, const std::string &w);
  void check_file_name(MeshArgs &a) const;
};

}  // namespace dembridge
