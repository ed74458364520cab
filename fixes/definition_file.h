// Definitions read from a file by the Parmec-style fixes (`file FILENAME`): rank 0 reads it, `#`
// starts a comment, every rank gets the same whitespace-separated words.
#pragma once

#include "lammps.h"

#include <string>
#include <vector>

namespace dembridge {

// Errors (file cannot be opened) name `command` and the path.
std::vector<std::string> read_definition_words(LAMMPS_NS::LAMMPS *lmp, const std::string &path, const std::string &command);

}  // namespace dembridge
