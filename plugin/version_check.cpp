#include "version_check.h"

#include <cstring>

namespace dembridge {

VersionVerdict check_host_version(int built, int host, const char *host_string, const char *override_env)
{
  if (built == host) return {true, ""};
  const std::string what = "dembridge plugin was built for LAMMPS " + std::to_string(built) +
      " but is loaded into LAMMPS " + std::to_string(host) + " (" + (host_string ? host_string : "?") +
      "); class layouts differ between versions";
  const bool forced = override_env && *override_env && std::strcmp(override_env, "0") != 0;
  if (forced) return {true, "WARNING: " + what + ", loading anyway because DEMBRIDGE_ALLOW_VERSION_MISMATCH is set"};
  return {false, "ERROR: " + what + ", so no styles were registered. Rebuild dembridge against this LAMMPS "
                 "(cmake -DLAMMPS_DIR=...) or set DEMBRIDGE_ALLOW_VERSION_MISMATCH=1 at your own risk."};
}

}  // namespace dembridge
