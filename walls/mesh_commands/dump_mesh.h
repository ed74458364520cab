// dump mesh/stl and dump mesh/vtk: LIGGGHTS 3.8's mesh output lines as real LAMMPS dump styles
// (doc/fix_mesh_surface.md, "Output"), so a LIGGGHTS deck's dump lines run unchanged:
//   dump ID group mesh/stl N FILE [local|all] [binary] [MESHID ...]
//   dump ID group mesh/vtk N FILE [output face] KEYWORD ... [MESHID ...]
// Without mesh IDs: every fix mesh/surface(/stress) defined before the dump. Keywords and mesh
// IDs in any order. The files are written by mesh_output.h, as those of fix mesh/dump.
// dump_modify: only 'first', 'every' and 'every/time' act on these dumps (LAMMPS's Output reads them);
// any other keyword is an ERROR naming it (at the dump_modify line when it reaches modify_param(), at
// the next run for those liblammps's Dump handles itself).
#pragma once

#include "self_writing_dump.h"
#include "mesh_output.h"

#include <vector>

namespace dembridge {

class MeshArgs;

class DumpMesh : public SelfWritingDump {
 public:
  DumpMesh(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  void write() override;  // the whole frame: the base class's per-atom machinery is not used

 protected:
  void init_style() override;
  int modify_param(int narg, char **arg) override;

 private:
  MeshOutput out_;
  bool stl_keyword(MeshArgs &a, const std::string &w);
  bool vtk_keyword(MeshArgs &a, const std::string &w);
  void check_file_name(MeshArgs &a) const;
  std::vector<unsigned char> modify_fields_at_creation_;  // dump_modify_snapshot() at creation
  [[noreturn]] void unsupported_modify_keyword(const std::string &keyword);
};

}  // namespace dembridge
