// fix nve/sphere with the plugin loaded: LAMMPS's fix nve/sphere (velocity Verlet of finite-size spheres) in a
// loop over the flat per-atom arrays, four atoms at a time with AVX2 (sphere_verlet_kernel.h): bitwise the
// built-in's numbers in about a third of its instructions per atom. Only the plain form (and 'disc') comes here;
// 'update dipole ...' and run_style respa go to the built-in (doc/fix_nve_sphere.md).
#pragma once

#include "fix.h"

#include <string>

namespace dembridge {

class FixNVESphereFlat : public LAMMPS_NS::Fix {
 public:
  FixNVESphereFlat(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void initial_integrate(int) override;
  void final_integrate() override;
  void reset_dt() override;

 private:
  std::string cmd_;       // "fix ID nve/sphere", for messages
  double inertia_ = 0.4;  // moment of inertia prefactor: 0.4 sphere, 0.5 disc
  double dtv_ = 0.0, dtf_ = 0.0;
  template <bool Drift> void half_step();
};

}  // namespace dembridge
