// fix ID group property/global NAME STYLE values...: LIGGGHTS-compatible global material
// properties (spec granular-models §3). Parsing lives in property/global_property.*.
#pragma once

#include "fix.h"
#include "global_property.h"

namespace dembridge {

class FixPropertyGlobal : public LAMMPS_NS::Fix {
 public:
  FixPropertyGlobal(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override { return 0; }
  const property::GlobalProperty &property() const { return prop_; }

  // The property/global fixes currently defined, to look up a name (nullptr if none).
  static const property::GlobalProperty *find(LAMMPS_NS::LAMMPS *lmp, const std::string &name);

 private:
  property::GlobalProperty prop_;
};

}  // namespace dembridge
