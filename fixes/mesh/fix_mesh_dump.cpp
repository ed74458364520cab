#include "fix_mesh_dump.h"

#include "fix_mesh_surface.h"
#include "mesh_args.h"
#include "mesh_writer.h"
#include "style_registry.h"

#include "comm.h"
#include "error.h"
#include "update.h"

#include <fstream>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;

namespace dembridge {

FixMeshDump::FixMeshDump(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const std::string cmd = std::string("fix mesh/dump (id ") + id + ")";
  MeshArgs a(lmp, cmd, narg, arg, 3);
  nevery = a.integer("N (output interval)");
  if (nevery < 1) a.fail("N", "expected an output interval >= 1");
  const std::string fmt = a.word("format");
  if (fmt != "vtk" && fmt != "stl") a.fail("format '" + fmt + "'", "expected vtk or stl");
  vtk_ = fmt == "vtk";
  file_ = a.word("file name");
  while (!a.done()) mesh_ids_.push_back(a.word("mesh ID"));
  if (mesh_ids_.empty()) a.fail("mesh IDs", "expected at least one fix mesh/surface ID after the file name");
  for (const auto &m : mesh_ids_) FixMeshSurface::find(lmp, m, cmd);
}

int FixMeshDump::setmask() { return END_OF_STEP; }

void FixMeshDump::init()
{
  for (const auto &m : mesh_ids_) FixMeshSurface::find(lmp, m, std::string("fix mesh/dump (id ") + id + ")");
}

void FixMeshDump::write()
{
  if (update->ntimestep % nevery) return;
  std::vector<mesh::MeshFrame> frames;
  for (const auto &mid : mesh_ids_) {
    FixMeshSurface *m = FixMeshSurface::find(lmp, mid, "fix mesh/dump");
    frames.push_back({&m->mesh(), m->triangle_forces_all(), mid.c_str()});  // collective
  }
  if (comm->me != 0) return;
  std::string name = file_;
  if (const auto star = name.find('*'); star != std::string::npos)
    name.replace(star, 1, std::to_string(update->ntimestep));
  std::ofstream os(name);
  if (!os) error->one(FLERR, std::string("fix mesh/dump (id ") + id + "): cannot open '" + name + "' for writing");
  if (vtk_) mesh::write_vtk(os, frames, "dembridge mesh");
  else mesh::write_stl(os, frames);
}

static void *create_fix_mesh_dump(void *lmp, int narg, char **arg)
{
  return new FixMeshDump(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_mesh_dump("fix", "mesh/dump", "mesh output (VTK or STL) every N steps", create_fix_mesh_dump);

}  // namespace dembridge
