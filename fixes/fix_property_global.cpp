#include "fix_property_global.h"

#include "error.h"
#include "modify.h"
#include "style_registry.h"

#include <string>
#include <vector>

using namespace LAMMPS_NS;

namespace dembridge {

FixPropertyGlobal::FixPropertyGlobal(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  register_dump_styles(lmp);  // dump custom/vtk etc. in this LAMMPS instance (style_registry.h)
  const std::string prefix = std::string("Fix property/global (id ") + id + "): ";
  try {
    prop_ = property::GlobalProperty::parse(std::vector<std::string>(arg + 3, arg + narg));
  } catch (const property::PropertyError &e) {
    error->all(FLERR, prefix + e.what());
  }
  for (Fix *f : modify->get_fix_by_style("^property/global$")) {
    if (f == this || std::string(f->id) == id) continue;  // redefinition of the same ID replaces it
    if (static_cast<FixPropertyGlobal *>(f)->prop_.name() == prop_.name())
      error->all(FLERR, prefix + "There is already a fix that registers a variable of the same name '" + prop_.name() +
                            "' (fix " + f->id + "); unfix it first or use another name");
  }
}

const property::GlobalProperty *FixPropertyGlobal::find(LAMMPS *lmp, const std::string &name)
{
  for (Fix *f : lmp->modify->get_fix_by_style("^property/global$")) {
    const auto &p = static_cast<FixPropertyGlobal *>(f)->prop_;
    if (p.name() == name) return &p;
  }
  return nullptr;
}

static void *create_fix_property_global(void *lmp, int narg, char **arg)
{
  return new FixPropertyGlobal(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_property_global("fix", "property/global",
                                             "LIGGGHTS-compatible global material properties", create_fix_property_global);

}  // namespace dembridge
