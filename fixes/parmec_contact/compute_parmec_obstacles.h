// compute ID group parmec/obstacles FIX_ID: the triangles of the OBSTACLEs of fix parmec/granular FIX_ID at
// their current pose, as a local array (rank 0 holds every row: the obstacles are replicated on all ranks).
// Columns: obstacle index (definition order), triangle colour, then x y z of the three nodes. The Parmec
// front end dumps it at its output times to draw moving obstacles (doc/fix_parmec_granular.md, "Output").
#pragma once

#include "compute.h"

#include <string>
#include <vector>

namespace dembridge {

class ComputeParmecObstacles : public LAMMPS_NS::Compute {
 public:
  static constexpr int kCols = 11;
  ComputeParmecObstacles(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  void init() override;
  void compute_local() override;
  double memory_usage() override;

 private:
  std::string fix_id_;
  std::vector<double> data_;
  std::vector<double *> rows_;  // array_local points here
};

}  // namespace dembridge
