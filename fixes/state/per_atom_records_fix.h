// PerAtomRecordsFix: the LAMMPS per-atom callbacks of a fix whose state is per-atom lists of records
// (RecordLists), written once: grow/copy/set arrays (sorting, deletion, new atoms), pack/unpack exchange
// (migration), pack/unpack/size restart (restart files). PerAtomStateFix (the Parmec entities) and
// FixWallGran (wall contacts) derive from it; doc/per_atom_state.md.
#pragma once

#include "fix.h"

#include "record_lists.h"

#include <string>

namespace dembridge::state {

class PerAtomRecordsFix : public LAMMPS_NS::Fix {
 public:
  // record_size: doubles per record, key included. Sets restart_peratom and create_attribute, and
  // registers the GROW and RESTART callbacks.
  PerAtomRecordsFix(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg, int record_size);
  ~PerAtomRecordsFix() override;

  void grow_arrays(int nmax) override;
  void copy_arrays(int i, int j, int delflag) override;
  void set_arrays(int i) override;
  int pack_exchange(int i, double *buf) override;
  int unpack_exchange(int nlocal, double *buf) override;
  int pack_restart(int i, double *buf) override;
  void unpack_restart(int nlocal, int nth) override;
  int size_restart(int i) override;
  int maxsize_restart() override;
  double memory_usage() override;

 protected:
  const std::string cmd_;  // "fix ID style", the prefix of every message
  RecordLists records_;

  // The most records one atom may carry (sizes the exchange and restart buffers).
  void set_records_per_atom(int most);
  // After atom i's records were read from a restart file: ERROR if they do not belong to this fix's
  // definitions (the layout itself is checked before).
  virtual void check_restored(int i) { (void)i; }
  // Called first by every callback above (before records move, are packed, read or replaced): a fix that
  // keeps its states elsewhere between steps writes them into the records here.
  virtual void flush_records() {}
};

}  // namespace dembridge::state
