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
  return {false, what + ", so no styles were registered. Rebuild dembridge against this LAMMPS "
                "(cmake -DLAMMPS_DIR=...) or set DEMBRIDGE_ALLOW_VERSION_MISMATCH=1 at your own risk."};
}

std::string lammps_date(int num_ver)
{
  static const char *const months[] = {"Jan", "Feb", "Mar", "Apr", "May", "Jun",
                                       "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"};
  const int day = num_ver % 100, month = (num_ver / 100) % 100, year = num_ver / 10000;
  if (month < 1 || month > 12 || day < 1 || day > 31) return std::to_string(num_ver);
  return std::to_string(day) + " " + months[month - 1] + " " + std::to_string(year);
}

std::string load_banner(const char *dembridge_version, int built)
{
  return std::string("dembridge ") + dembridge_version + " loaded (built for LAMMPS " + lammps_date(built) + ", " +
         std::to_string(built) + ")";
}

}  // namespace dembridge
