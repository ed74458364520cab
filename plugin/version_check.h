// Decides whether the plugin may register into a host LAMMPS (kept LAMMPS-free for unit tests).
#pragma once

#include <string>

namespace dembridge {

struct VersionVerdict {
  bool accept;
  std::string message;  // why it was refused (the text of an ERROR), or a warning when an override was used
};

// built: numeric version compiled against (YYYYMMDD); host: lmp->num_ver; host_string: lmp->version.
// override_env: value of DEMBRIDGE_ALLOW_VERSION_MISMATCH (nullptr if unset).
VersionVerdict check_host_version(int built, int host, const char *host_string, const char *override_env);

// "22 Jul 2025" for 20250722: the form LAMMPS prints its own version in.
std::string lammps_date(int num_ver);

// The line the plugin prints when it registers, e.g.
// "dembridge 0.2.0 loaded (built for LAMMPS 22 Jul 2025, 20250722)".
std::string load_banner(const char *dembridge_version, int built);

}  // namespace dembridge
