// Decides whether the plugin may register into a host LAMMPS (kept LAMMPS-free for unit tests).
#pragma once

#include <string>

namespace dembridge {

struct VersionVerdict {
  bool accept;
  std::string message;  // why it was refused, or a warning when an override was used
};

// built: numeric version compiled against (YYYYMMDD); host: lmp->num_ver; host_string: lmp->version.
// override_env: value of DEMBRIDGE_ALLOW_VERSION_MISMATCH (nullptr if unset).
VersionVerdict check_host_version(int built, int host, const char *host_string, const char *override_env);

}  // namespace dembridge
