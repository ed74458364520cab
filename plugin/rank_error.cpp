#include "rank_error.h"

#include <chrono>
#include <cstdio>
#include <thread>

#include "comm.h"
#include "error.h"
#include "lammps.h"

namespace dembridge {

namespace {
// Long enough for a launcher on a loaded machine to read the pipes; paid only on the way out.
constexpr std::chrono::milliseconds kForwardTime{500};
}  // namespace

void fail_on_this_rank(LAMMPS_NS::LAMMPS *lmp, const char *file, int line, const std::string &message)
{
  try {
    lmp->error->one(file, line, message);
  } catch (...) {
    if (lmp->screen) std::fflush(lmp->screen);
    std::fflush(stdout);
    std::fflush(stderr);
    if (lmp->comm && lmp->comm->nprocs > 1) std::this_thread::sleep_for(kForwardTime);
    throw;
  }
}

}  // namespace dembridge
