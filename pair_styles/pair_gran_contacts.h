// PairGran's neighbour loop (see for_each_contact in pair_gran.h): the serial compute and the
// threaded /omp compute both run it and differ only in what they do with each contact. The loop
// itself is gran::run_pair_loop (pair_gran_kernel.h, LAMMPS-free, compiled per model).
#pragma once

#include "pair_gran.h"

namespace dembridge {

template <class Sink> void PairGran::for_each_contact(int ii_from, int ii_to, Sink &&sink)
{
  const gran::PairLoopError e = gran::run_pair_loop(loop_data(), ii_from, ii_to, sink);
  if (e.kind != gran::PairLoopError::None) loop_failed(e);
}

}  // namespace dembridge
