// fix ID group adapt N atom diameter v_NAME [reset no|yes]: LIGGGHTS 3.8's fix adapt with an atom-style
// variable NAME (LAMMPS's fix adapt takes equal-style variables only), as the LIGGGHTS packing tutorial
// grows its particles. Every N steps (and at setup) each atom of the group gets the diameter NAME gives
// it and keeps its density: rho = m / (4/3 pi r^3), r = d/2, m = 4/3 pi r^3 rho, in LIGGGHTS's order of
// operations. Ghost atoms get the new radius and mass by a forward communication at once. Any other
// fix adapt line goes to LAMMPS's built-in fix adapt.
#pragma once

#include "fix.h"

#include <string>
#include <vector>

namespace dembridge {

class FixAdaptLiggghts : public LAMMPS_NS::Fix {
 public:
  FixAdaptLiggghts(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void setup_pre_force(int) override;
  void pre_force(int) override;
  int pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc) override;
  void unpack_forward_comm(int n, int first, double *buf) override;

  // True when every adaptation of the line is 'atom diameter v_NAME' with NAME an atom-style variable.
  static bool is_liggghts_form(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);

 private:
  std::string variable_;
  int ivar_ = -1;
  std::vector<double> diameters_;
  void change_diameters();
};

}  // namespace dembridge
