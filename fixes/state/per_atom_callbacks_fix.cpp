#include "per_atom_callbacks_fix.h"

#include "atom.h"
#include "modify.h"

using namespace LAMMPS_NS;

namespace dembridge::state {

void PerAtomCallbacksFix::attach(AtomLists &lists)
{
  lists_ = &lists;
  restart_peratom = 1;
  create_attribute = 1;
  maxexchange = 1;
  lists_->resize(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
}

PerAtomCallbacksFix::~PerAtomCallbacksFix()
{
  // Not when a derived constructor failed (an ERROR in the arguments): the fix was never stored, and
  // delete_callback would ERROR inside a destructor (std::terminate) or hit a fix of the same ID.
  if (lists_ && modify->get_fix_by_id(id) == this) {
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
  }
}

void PerAtomCallbacksFix::grow_arrays(int nmax)
{
  flush_records();
  lists_->resize(nmax);
}

void PerAtomCallbacksFix::copy_arrays(int i, int j, int)
{
  flush_records();
  lists_->copy(i, j);
}

void PerAtomCallbacksFix::set_arrays(int i)
{
  flush_records();
  lists_->clear(i);
}

int PerAtomCallbacksFix::pack_exchange(int i, double *buf)
{
  flush_records();
  return lists_->pack(i, buf);
}

// The exchange buffers must hold every atom's entries: maxexchange grows with what arrives.
int PerAtomCallbacksFix::unpack_exchange(int nlocal, double *buf)
{
  flush_records();
  const int n = lists_->unpack(nlocal, buf);
  fit_exchange(n);
  return n;
}

// Restart layout per atom: [total size, packed atom] (LAMMPS skips fixes by the total size).
int PerAtomCallbacksFix::size_restart(int i)
{
  flush_records();
  return 1 + lists_->packed_size(i);
}

int PerAtomCallbacksFix::maxsize_restart()
{
  flush_records();
  return 1 + maxexchange;
}

int PerAtomCallbacksFix::pack_restart(int i, double *buf)
{
  flush_records();
  const int n = lists_->pack(i, buf + 1);
  buf[0] = 1 + n;
  return 1 + n;
}

void PerAtomCallbacksFix::unpack_restart(int nlocal, int nth)
{
  if (!lists_) return;  // never attached: the data belong to the fix that replaces this one
  flush_records();
  const double *extra = atom->extra[nlocal];
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[m]);
  const double *block = extra + m;
  // Another layout would be read as garbage.
  if (!lists_->is_packed_atom(block + 1, static_cast<int>(block[0]) - 1)) {
    restart_mismatch(nlocal);
    return;
  }
  fit_exchange(lists_->unpack(nlocal, block + 1));
  check_restored(nlocal);
}

}  // namespace dembridge::state
