// An error only this rank found (LAMMPS's error->one), reported so the message survives the abort.
#pragma once

#include <string>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace dembridge {

// Error::one writes the message and its exception ends in MPI_Abort. With several ranks MPICH's
// launcher can tear the job down on that abort before it has forwarded this rank's output, and the
// user sees a failed run without the ERROR line (measured: 2 in 200 two-rank runs with piped output).
// So the message is flushed and the launcher gets time to forward it before the exception goes on.
[[noreturn]] void fail_on_this_rank(LAMMPS_NS::LAMMPS *lmp, const char *file, int line, const std::string &message);

}  // namespace dembridge
