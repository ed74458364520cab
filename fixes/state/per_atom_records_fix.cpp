#include "per_atom_records_fix.h"

#include "atom.h"
#include "error.h"
#include "modify.h"

using namespace LAMMPS_NS;

namespace dembridge::state {

PerAtomRecordsFix::PerAtomRecordsFix(LAMMPS *lmp, int narg, char **arg, int record_size) :
    Fix(lmp, narg, arg), cmd_(std::string("fix ") + arg[0] + " " + arg[2]), records_(record_size)
{
  restart_peratom = 1;
  create_attribute = 1;
  maxexchange = 1;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
}

PerAtomRecordsFix::~PerAtomRecordsFix()
{
  // Not when a derived constructor failed (an ERROR in the arguments): the fix was never stored, and
  // delete_callback would ERROR inside a destructor (std::terminate) or hit a fix of the same ID.
  if (modify->get_fix_by_id(id) == this) {
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
  }
}

void PerAtomRecordsFix::set_records_per_atom(int most)
{
  maxexchange = 1 + most * records_.record_size();
}

void PerAtomRecordsFix::grow_arrays(int nmax)
{
  flush_records();
  records_.resize(nmax);
}

void PerAtomRecordsFix::copy_arrays(int i, int j, int)
{
  flush_records();
  records_.copy(i, j);
}

void PerAtomRecordsFix::set_arrays(int i)
{
  flush_records();
  records_.clear(i);
}

int PerAtomRecordsFix::pack_exchange(int i, double *buf)
{
  flush_records();
  return records_.pack(i, buf);
}

int PerAtomRecordsFix::unpack_exchange(int nlocal, double *buf)
{
  flush_records();
  return records_.unpack(nlocal, buf);
}

// Restart layout per atom: [total size, n, n values] (LAMMPS skips fixes by the total size).
int PerAtomRecordsFix::size_restart(int i)
{
  flush_records();
  return 1 + records_.packed_size(i);
}

int PerAtomRecordsFix::maxsize_restart()
{
  return 1 + maxexchange;
}

int PerAtomRecordsFix::pack_restart(int i, double *buf)
{
  flush_records();
  const int n = records_.pack(i, buf + 1);
  buf[0] = 1 + n;
  return 1 + n;
}

void PerAtomRecordsFix::unpack_restart(int nlocal, int nth)
{
  flush_records();
  const double *extra = atom->extra[nlocal];
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[m]);
  const double *block = extra + m;
  // Another record size or an older layout would be read as garbage: refuse it.
  const int values = static_cast<int>(block[1]);
  if (static_cast<int>(block[0]) != 2 + values || values < 0 || values % records_.record_size() != 0)
    error->one(FLERR, fmt::format("{}: the restart file's data for atom {} are not whole records of {} values (the fix "
                                  "had another model, or another dembridge version wrote the file): define the fix as "
                                  "before write_restart", cmd_, atom->tag[nlocal], records_.record_size()));
  records_.unpack(nlocal, block + 1);
  check_restored(nlocal);
}

double PerAtomRecordsFix::memory_usage()
{
  return records_.bytes(atom->nlocal);
}

}  // namespace dembridge::state
