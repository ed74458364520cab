// The plugin's granular pair styles threaded under LAMMPS's OPENMP conventions: `package omp N`,
// `-sf omp`, `suffix omp` select STYLE/omp, registered here for every dembridge pair style, so the
// suffix never falls back to LAMMPS's built-in gran/*/omp (which know neither the LIGGGHTS syntax
// nor our contact history).
//
// Threads split the neighbour list into blocks of rows (atoms i): each contact, and its history
// slot, belongs to one thread. Forces reach the atoms through PairForceGather (threads/), which
// keeps the serial order of every addition: the results are bit-identical to the plain style for
// any thread count.
#pragma once

#include "pair_force_gather.h"
#include "pair_gran.h"

#include <vector>

namespace dembridge {

class PairGranOMP : public PairGran {
 public:
  PairGranOMP(LAMMPS_NS::LAMMPS *lmp, const char *base_style);

  void compute(int eflag, int vflag) override;
  void init_style() override;
  double memory_usage() override;
  // "nthreads": the OpenMP threads that took part in the last compute (int, dim 0)
  void *extract(const char *name, int &dim) override;

 private:
  struct GatherSink;
  threads::PairForceGather gather_;
  std::vector<double> row_weight_;  // expected cost per list row, for the blocks' balance
  LAMMPS_NS::bigint gather_build_ = -1;  // neighbor->ncalls when the gather index was built
  int threads_used_ = 1;
  bool report_threads_ = true;  // log the threads used at the first compute of each run

  int requested_threads() const;
  void index_list(int nreceive, int nblocks);
  void tally_virial();
  void report_threads();
};

}  // namespace dembridge
