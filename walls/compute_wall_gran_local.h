// compute ID group wall/gran/local WALLFIX
// Per-contact output of a dembridge fix wall/gran: one row per particle-wall contact of the last
// force evaluation, columns id mesh tri delta Fn Fx Fy Fz Ftx Fty Ftz cpx cpy cpz. The wall fix
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

  static constexpr int kCols = 14;

 private:
  std::string wall_id_;
  FixWallGran *wall_ = nullptr;
  std::vector<double> data_;
  std::vector<double *> rows_;
  FixWallGran *find_wall();
};

}  // namespace dembridge
