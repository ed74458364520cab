// Under `package omp N` without `suffix omp`, the fixes that have a threaded /omp twin (LAMMPS's nve/sphere/omp,
// gravity/omp, the plugin's nve/bpm/sphere/omp, ...) still run on one thread, and a threaded fix's speed-up stops
// there. The note names them once per run in the log (doc/fix_nve_bpm_sphere_omp.md).
#pragma once

#include <string>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace dembridge {

// On rank 0, when comm->nthreads > 1: "<who>: under package omp N, fix ID (STYLE), ... ran on one thread; their
// /omp variants would thread them (suffix omp, or -sf omp)", for every fix whose STYLE/omp exists. Nothing otherwise.
void note_serial_fixes(LAMMPS_NS::LAMMPS *lmp, const std::string &who);

}  // namespace dembridge
