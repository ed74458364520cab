// Built in place of the plugin's dump styles when they cannot be (plugin/CMakeLists.txt): each name is a
// dump style whose creator stops with the reason, before any Dump object of unknown layout is made.
#include "dump_unavailable.h"
#include "style_registry.h"

#include "error.h"
#include "lammps.h"

namespace dembridge {

namespace {
void *refuse(void *lmp, int narg, char **arg)
{
  auto *host = static_cast<LAMMPS_NS::LAMMPS *>(lmp);
  const std::string id = narg > 0 ? arg[0] : "?";
  const std::string style = narg > 2 ? arg[2] : "?";
  host->error->all(FLERR, dump_unavailable_message(style, id, DEMBRIDGE_DUMP_MISSING_WHY));
  return nullptr;
}
}  // namespace

static RegisterStyle reg_mesh_stl("dump", "mesh/stl", "LIGGGHTS dump mesh/stl (not built)", refuse);
static RegisterStyle reg_mesh_vtk("dump", "mesh/vtk", "LIGGGHTS dump mesh/vtk (not built)", refuse);
static RegisterStyle reg_mesh_gran_vtk("dump", "mesh/gran/VTK", "LIGGGHTS dump mesh/gran/VTK (not built)", refuse);
static RegisterStyle reg_stl("dump", "stl", "LIGGGHTS dump stl (not built)", refuse);
static RegisterStyle reg_custom_vtk("dump", "custom/vtk", "LIGGGHTS dump custom/vtk (not built)", refuse);

}  // namespace dembridge
