// The dump styles of a plugin built without them (a LAMMPS with no dump.h and of another version than
// the one plugin/lammps_dump_base.h was measured on): the dump command refuses them and says why,
// instead of LAMMPS's bare "Unrecognized dump style". LAMMPS-free, unit tested.
#pragma once

#include <string>

namespace dembridge {

// "dump mesh/stl (id d1) is not available in this build of dembridge: <why>; <what to use instead>"
std::string dump_unavailable_message(const std::string &style, const std::string &id, const std::string &why);

}  // namespace dembridge
