#include "fix_mesh_dump.h"

#include "mesh_args.h"
#include "style_registry.h"

#include "update.h"

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;

namespace dembridge {

FixMeshDump::FixMeshDump(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  out_.caller = std::string("fix mesh/dump (id ") + id + ")";
  MeshArgs a(lmp, out_.caller, narg, arg, 3);
  nevery = a.integer("N (output interval)");
  if (nevery < 1) a.fail("N", "expected an output interval >= 1");
  const std::string fmt = a.word("format");
  if (fmt != "vtk" && fmt != "stl") a.fail("format '" + fmt + "'", "expected vtk or stl");
  out_.vtk = fmt == "vtk";
  out_.file = a.word("file name");
  while (!a.done()) out_.mesh_ids.push_back(a.word("mesh ID"));
  if (out_.mesh_ids.empty()) a.fail("mesh IDs", "expected at least one fix mesh/surface ID after the file name");
  check_mesh_ids(lmp, out_);
}

int FixMeshDump::setmask() { return END_OF_STEP; }

void FixMeshDump::init() { check_mesh_ids(lmp, out_); }

void FixMeshDump::write()
{
  if (update->ntimestep % nevery == 0) write_mesh_frame(lmp, out_);
}

static RegisterStyle reg_fix_mesh_dump("fix", "mesh/dump", "mesh output (VTK or STL) every N steps", create_fix<FixMeshDump>);

}  // namespace dembridge
