// The mesh fixes' name for the plugin's argument reader (fixes/command_args.h); a class, not an alias,
// so that the mesh headers can declare it ahead.
#pragma once

#include "command_args.h"
#include "mesh_vec3.h"

namespace dembridge {
class MeshArgs : public CommandArgs {
 public:
  using CommandArgs::CommandArgs;
};
}  // namespace dembridge
