#include "dump_unavailable.h"

namespace dembridge {

namespace {
const char *instead(const std::string &style)
{
  if (style == "custom/vtk") return "LAMMPS's dump custom writes the same per-atom columns as text";
  return "fix mesh/dump writes the same mesh files";
}
}  // namespace

std::string dump_unavailable_message(const std::string &style, const std::string &id, const std::string &why)
{
  return "dump " + style + " (id " + id + ") is not available in this build of dembridge: " + why + "; " +
         instead(style);
}

}  // namespace dembridge
