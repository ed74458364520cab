// fix nve/bpm/sphere/omp: LAMMPS's fix nve/bpm/sphere (velocity Verlet for finite-size spheres that carry a
// quaternion, atom style bpm/sphere) with its atom loops on the OpenMP threads of `package omp N`. LAMMPS's
// OPENMP package has nve/sphere/omp but no nve/bpm/sphere/omp, so under `-sf omp` the rotating spring deck
// integrated on one thread; with the plugin loaded the suffix picks this fix (doc/fix_nve_bpm_sphere_omp.md).
//
// Every atom is updated on its own with the built-in's expressions in the built-in's order (and its very
// quaternion routine, MathExtra::richardson_sphere of liblammps), so the result is bitwise the built-in's for
// any thread count (tests/python/test_fix_nve_bpm_sphere_omp.py).
#pragma once

#include "fix.h"

#include <string>

namespace dembridge {

class FixNVEBPMSphereOMP : public LAMMPS_NS::Fix {
 public:
  FixNVEBPMSphereOMP(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void final_integrate() override;
  void reset_dt() override;

 private:
  std::string cmd_;        // "fix nve/bpm/sphere/omp" (or the style as written), for messages
  double inertia_ = 0.4;   // moment of inertia prefactor: 0.4 sphere, 0.5 disc (2d, keyword 'disc')
  double dtv_ = 0.0;       // dt
  double dtf_ = 0.0;       // dt/2 in force units (ftm2v)
  int threads() const;     // the threads of `package omp N` (1 without OpenMP)
  struct Step;
  Step step() const;
  template <class Per> void each_atom(Per per) const;
};

}  // namespace dembridge
