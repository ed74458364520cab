// Every style of the plugin registers itself here with one static object in its own .cpp, so
// adding a style never touches the plugin entry point.
#pragma once

#include <vector>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace dembridge {

using PairFactory = void *(*)(void *lmp);
using FixFactory = void *(*)(void *lmp, int narg, char **arg);

struct StyleEntry {
  const char *kind;  // "pair", "fix", "compute", "command", "dump"
  const char *name;
  const char *info;
  PairFactory v1 = nullptr;  // pair, command
  FixFactory v2 = nullptr;   // fix, compute, dump
  // A fix that also serves the built-in style of the same name (other syntax): the plugin entry
  // stores the built-in's creator here before overriding it, so the fix can delegate to it.
  FixFactory *builtin = nullptr;
};

std::vector<StyleEntry> &style_registry();

// The plugin loader of LAMMPS 22 Jul 2025 skips dump styles ("not yet implemented") and does not
// remember them for the next LAMMPS instance of the process or for `clear`: the dump styles are
// entered into Output's public style map here, by lammpsplugin_init and again by every fix
// mesh/surface (a mesh dump line always follows one), fix property/global and command communicate (one
// of them comes before the dump lines of every LIGGGHTS deck). `plugin unload` does not know them; the plugin
// is linked -z nodelete so that they stay valid after every other style was unloaded (CMakeLists.txt).
void register_dump_styles(LAMMPS_NS::LAMMPS *lmp);

struct RegisterStyle {
  RegisterStyle(const char *kind, const char *name, const char *info, PairFactory f)
  {
    style_registry().push_back({kind, name, info, f, nullptr});
  }
  RegisterStyle(const char *kind, const char *name, const char *info, FixFactory f, FixFactory *builtin = nullptr)
  {
    style_registry().push_back({kind, name, info, nullptr, f, builtin});
  }
};

// The factory of a fix (or compute) class T constructed as T(lmp, narg, arg).
template <class T> void *create_fix(void *lmp, int narg, char **arg)
{
  return new T(static_cast<LAMMPS_NS::LAMMPS *>(lmp), narg, arg);
}

}  // namespace dembridge
