// The mesh fixes' name for the plugin's argument reader (fixes/command_args.h).
#pragma once

#include "command_args.h"
#include "mesh_vec3.h"

namespace dembridge {
using MeshArgs = CommandArgs;
}  // namespace dembridge
