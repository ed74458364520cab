// compute ID group pair/gran/local [include both|either]
// Per-contact output of the dembridge granular pair styles: one row per touching pair, columns
// id_i id_j delta Fn Ft_x Ft_y Ft_z [history...]. The contact law is re-evaluated on a COPY of the
// stored history with history_update=false, so the run is bitwise unchanged by this compute.
// Documentation: doc/compute_pair_gran_local.md.
#pragma once

#include "compute.h"

#include <vector>

namespace dembridge {

class PairGran;

class ComputePairGranLocal : public LAMMPS_NS::Compute {
 public:
  ComputePairGranLocal(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  void init() override;
  void compute_local() override;
  int pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc) override;
  void unpack_forward_comm(int n, int first, double *buf) override;
  double memory_usage() override;

 private:
  static constexpr int kFixedCols = 7;  // id_i id_j delta Fn Ft_x Ft_y Ft_z
  int nhist_ = 0;                       // history columns, fixed at construction
  bool either_ = false;                 // include a pair if either atom is in the group (default: both)
  std::vector<double> data_;            // rows, size_local_cols doubles each
  std::vector<double *> rows_;          // array_local points here
  std::vector<double> ghost_vo_;        // current v and omega of ghost atoms (6 per atom index)

  PairGran *dembridge_pair(const char *when);
  void refresh_ghost_velocities();
};

}  // namespace dembridge
