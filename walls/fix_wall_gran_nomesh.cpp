// Temporary: built while fix mesh/surface (fixes/mesh/) is not on this branch yet.
#include "fix_wall_gran.h"

#include "error.h"

namespace dembridge {

void FixWallGran::init_meshes()
{
  if (spec_.is_mesh) error->all(FLERR, me_ + ": mesh walls need fix mesh/surface, which this build does not have");
}

void FixWallGran::mesh_pass(bool) {}

}  // namespace dembridge
