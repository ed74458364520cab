// PerAtomCallbacksFix: the LAMMPS per-atom callbacks of a fix whose per-atom state moves with its atoms,
// written once over the fix's AtomLists: grow/copy/set arrays (sorting, deletion, new atoms), pack/unpack
// exchange (migration), pack/unpack/size restart (restart files). PerAtomRecordsFix (Parmec fixes,
// fix wall/gran) and FixContactHistory (the pair styles' contact history) derive from it; the storage
// stays each fix's own (the contact history's pool is rebuilt at every neighbour rebuild, which record
// lists would make ~1 % slower). doc/per_atom_state.md.
#pragma once

#include "atom_lists.h"
#include "fix.h"

namespace dembridge::state {

class PerAtomCallbacksFix : public LAMMPS_NS::Fix {
 public:
  ~PerAtomCallbacksFix() override;

  void grow_arrays(int nmax) override;
  void copy_arrays(int i, int j, int delflag) override;
  void set_arrays(int i) override;
  int pack_exchange(int i, double *buf) override;
  int unpack_exchange(int nlocal, double *buf) override;
  int pack_restart(int i, double *buf) override;
  void unpack_restart(int nlocal, int nth) override;
  int size_restart(int i) override;
  int maxsize_restart() override;

 protected:
  PerAtomCallbacksFix(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {}

  // From the derived constructor, once the storage exists: sizes it for the atoms present, registers the
  // GROW and RESTART callbacks, sets restart_peratom, create_attribute and maxexchange 1 (an atom without
  // entries). A fix that never attaches ignores restart data (the contact history's placeholder).
  void attach(AtomLists &lists);

  // The three hooks.
  // Called first by every callback (before entries move, are packed, read or replaced): a fix that keeps
  // its states elsewhere between steps writes them into the storage here.
  virtual void flush_records() {}
  // After atom i's entries were read from a restart file: the fix's own checks (an ERROR if they do not
  // belong to its definitions) or bookkeeping.
  virtual void check_restored(int i) { (void)i; }
  // Atom i's block in the restart file is not in this storage's layout (another model or version): an
  // ERROR, or start the atom without entries.
  virtual void restart_mismatch(int i) = 0;

 private:
  AtomLists *lists_ = nullptr;
  void fit_exchange(int n)
  {
    if (n > maxexchange) maxexchange = n;
  }
};

}  // namespace dembridge::state
