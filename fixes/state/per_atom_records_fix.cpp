#include "per_atom_records_fix.h"
#include "rank_error.h"

#include "atom.h"
#include "error.h"

using namespace LAMMPS_NS;

namespace dembridge::state {

PerAtomRecordsFix::PerAtomRecordsFix(LAMMPS *lmp, int narg, char **arg, int record_size) :
    PerAtomCallbacksFix(lmp, narg, arg), cmd_(std::string("fix ") + arg[0] + " " + arg[2]), records_(record_size)
{
  attach(records_);
}

void PerAtomRecordsFix::set_records_per_atom(int most)
{
  maxexchange = 1 + most * records_.record_size();
}

void PerAtomRecordsFix::restart_mismatch(int i)
{
  fail_on_this_rank(lmp, FLERR, fmt::format("{}: the restart file's data for atom {} are not whole records of {} values (the fix "
                                            "had another model, or another dembridge version wrote the file): define the fix as "
                                            "before write_restart", cmd_, atom->tag[i], records_.record_size()));
}

double PerAtomRecordsFix::memory_usage()
{
  return records_.bytes(atom->nlocal);
}

}  // namespace dembridge::state
