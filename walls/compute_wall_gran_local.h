// compute ID group wall/gran/local WALLFIX
// Per-contact output of a dembridge fix wall/gran: one row per particle-wall contact of the last
// force evaluation, columns id mesh tri delta Fn Fx Fy Fz Ftx Fty Ftz cpx cpy cpz, then the contact's
// history values (tangential spring 3, epsd rolling spring 3, as the model has them). The wall fix
// records the values it applied, so the run is bitwise unchanged by this compute.
// Documentation: doc/compute_wall_gran_local.md.
#pragma once

#include "compute.h"

#include <string>
#include <vector>

namespace dembridge {

class FixWallGran;

class ComputeWallGranLocal : public LAMMPS_NS::Compute {
 public:
  ComputeWallGranLocal(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  void init() override;
  void compute_local() override;
  double memory_usage() override;

  static constexpr int kFixedCols = 14;

 private:
  std::string wall_id_;
  int ncols_ = kFixedCols;
  FixWallGran *wall_ = nullptr;
  std::vector<double> data_;
  std::vector<double *> rows_;
  FixWallGran *find_wall();
};

}  // namespace dembridge
