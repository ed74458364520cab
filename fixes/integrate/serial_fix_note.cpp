// See serial_fix_note.h.
#include "serial_fix_note.h"

#include "comm.h"
#include "fix.h"
#include "lammps.h"
#include "modify.h"
#include "utils.h"

namespace dembridge {

void note_serial_fixes(LAMMPS_NS::LAMMPS *lmp, const std::string &who)
{
  if (lmp->comm->nthreads <= 1 || lmp->comm->me != 0 || !lmp->modify->fix_map) return;
  std::string serial;
  for (const LAMMPS_NS::Fix *f : lmp->modify->get_fix_list()) {
    const std::string style = f->style;
    if (lmp->modify->fix_map->count(style + "/omp"))
      serial += (serial.empty() ? "" : ", ") + std::string("fix ") + f->id + " (" + style + ")";
  }
  if (!serial.empty())
    LAMMPS_NS::utils::logmesg(lmp, "{}: under package omp {}, {} ran on one thread; their /omp variants would thread "
                                   "them (suffix omp, or -sf omp)\n", who, lmp->comm->nthreads, serial);
}

}  // namespace dembridge
