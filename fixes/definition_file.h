// Definitions read from a file by the Parmec-style fixes (`file FILENAME`): rank 0 reads it, `#`
// starts a comment, every rank gets the same whitespace-separated words.
#pragma once

#include "lammps.h"

#include <functional>
#include <string>
#include <vector>

namespace dembridge {

// Errors (file cannot be opened) name `command` and the path.
std::vector<std::string> read_definition_words(LAMMPS_NS::LAMMPS *lmp, const std::string &path, const std::string &command);

// Reads `path` and hands its words to parse(words, "file PATH") while the file is open in the chain of
// nested `file` keywords: a file that includes itself, directly or through others, is an ERROR naming
// the chain instead of an endless recursion.
void parse_definition_file(LAMMPS_NS::LAMMPS *lmp, const std::string &path, const std::string &command,
                           const std::function<void(const std::vector<std::string> &, const std::string &)> &parse);

}  // namespace dembridge
