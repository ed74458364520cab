// fix particletemplate/sphere (doc/fix_particletemplate_sphere.md): one sphere kind for the insertion
// fixes, LIGGGHTS 3.8 syntax (radius and density `constant` only, as 3.8). Holds no per-atom data.
#pragma once

#include "fix.h"

#include "discrete_distribution.h"

#include <string>

namespace dembridge {

class FixParticleTemplateSphere : public LAMMPS_NS::Fix {
 public:
  FixParticleTemplateSphere(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override { return 0; }
  void init() override;
  const insertion::SphereTemplate &sphere() const { return sphere_; }
  int seed() const { return seed_; }
  // nullptr if `id` is not a fix particletemplate/sphere
  static FixParticleTemplateSphere *find(LAMMPS_NS::LAMMPS *lmp, const std::string &id);

 private:
  insertion::SphereTemplate sphere_;
  int seed_ = 0;
};

}  // namespace dembridge
