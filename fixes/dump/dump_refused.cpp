// LIGGGHTS 3.8's other VTK dump names: each an ERROR that says what to use instead, rather than
// LAMMPS's bare "Unrecognized dump style".
#include "self_writing_dump.h"
#include "style_registry.h"

#include "error.h"

#include <string>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {

const char *instead(const std::string &style)
{
  if (style == "custom/vtm" || style == "atom/vtk") return "use dump custom/vtk (legacy VTK, one file per frame)";
  if (style == "mesh/vtm") return "use dump mesh/vtk (or its LIGGGHTS name mesh/gran/VTK)";
  if (style == "local/gran/vtk")
    return "use compute pair/gran/local (or wall/gran/local) with LAMMPS's dump local";
  if (style == "decomposition/vtk") return "no replacement: LAMMPS's 'info' prints the processor grid";
  return "fix ave/euler is not available; LAMMPS's fix ave/chunk with compute chunk/atom bin/3d gives cell averages";
}

class DumpRefused : public SelfWritingDump {
 public:
  DumpRefused(LAMMPS *lmp, int narg, char **arg) : SelfWritingDump(lmp, narg, arg)
  {
    error->all(FLERR, std::string("dump ") + arg[2] + " (id " + arg[0] + "): LIGGGHTS's dump style '" + arg[2] +
                          "' is not available: " + instead(arg[2]));
  }

 protected:
  void init_style() override {}
};

}  // namespace

static RegisterStyle reg_custom_vtm("dump", "custom/vtm", "LIGGGHTS dump custom/vtm (refused)", create_fix<DumpRefused>);
static RegisterStyle reg_atom_vtk("dump", "atom/vtk", "LIGGGHTS dump atom/vtk (refused)", create_fix<DumpRefused>);
static RegisterStyle reg_mesh_vtm("dump", "mesh/vtm", "LIGGGHTS dump mesh/vtm (refused)", create_fix<DumpRefused>);
static RegisterStyle reg_local_gran_vtk("dump", "local/gran/vtk", "LIGGGHTS dump local/gran/vtk (refused)",
                                        create_fix<DumpRefused>);
static RegisterStyle reg_decomposition_vtk("dump", "decomposition/vtk", "LIGGGHTS dump decomposition/vtk (refused)",
                                           create_fix<DumpRefused>);
static RegisterStyle reg_euler_vtk("dump", "euler/vtk", "LIGGGHTS dump euler/vtk (refused)", create_fix<DumpRefused>);

}  // namespace dembridge
