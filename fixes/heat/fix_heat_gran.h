// fix ID group heat/gran initial_temperature T0 [contact_area overlap|projection|constant A]:
// LIGGGHTS 3.8's conduction between touching particles (also as heat/gran/conduction). It keeps the
// per-atom properties Temp, heatFlux and heatSource (fix property/atom, created or reset here), adds
// each contact's flux after the pair forces and steps T with the particle's thermalCapacity.
// Scalar output: the thermal energy sum(c m T); per-atom output: Temp.
#pragma once

#include "fix.h"

#include <vector>

namespace dembridge {

class FixPropertyAtomLiggghts;
class PairGran;

class FixHeatGran : public LAMMPS_NS::Fix {
 public:
  FixHeatGran(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  void post_constructor() override;
  int setmask() override;
  void init() override;
  void setup(int vflag) override;
  void initial_integrate(int vflag) override;
  void post_force(int vflag) override;
  void final_integrate() override;
  double compute_scalar() override;

 private:
  enum class Area { Overlap, Projection, Constant };
  void find_properties();
  std::vector<double> per_type(const char *name, int max_type);

  double T0_ = 0.0;
  Area area_ = Area::Overlap;
  double constant_area_ = 0.0;
  FixPropertyAtomLiggghts *temp_ = nullptr, *flux_ = nullptr, *source_ = nullptr;
  PairGran *pair_ = nullptr;
  std::vector<double> conductivity_, capacity_;  // per type, 1-based
};

}  // namespace dembridge
