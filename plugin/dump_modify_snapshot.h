// The dump styles of the plugin write their frames themselves, so the settings that liblammps's
// Dump::modify_params() stores for its own keywords (sort, pad, format, ...) would be accepted and
// ignored. A style takes a snapshot of those fields when it is created and compares it at init:
// the first keyword whose field changed is named in an ERROR (plugin/lammps_dump_base.h has the
// offsets). Against a LAMMPS that ships dump.h the fields are not measured: nothing is checked.
#pragma once

#include "lammps_dump_base.h"

#include <vector>

namespace dembridge {

std::vector<unsigned char> dump_modify_snapshot(const LAMMPS_NS::Dump *dump);

// The dump_modify keyword whose field differs from the snapshot, or nullptr.
const char *changed_dump_modify_keyword(const LAMMPS_NS::Dump *dump, const std::vector<unsigned char> &snapshot);

}  // namespace dembridge
