// PerAtomRecordsFix: a fix whose state is per-atom lists of records (RecordLists), moved with the atoms
// by PerAtomCallbacksFix. PerAtomStateFix (the Parmec entities) and FixWallGran (wall contacts) derive
// from it; doc/per_atom_state.md.
#pragma once

#include "per_atom_callbacks_fix.h"
#include "record_lists.h"

#include <string>

namespace dembridge::state {

class PerAtomRecordsFix : public PerAtomCallbacksFix {
 public:
  // record_size: doubles per record, key included.
  PerAtomRecordsFix(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg, int record_size);

  double memory_usage() override;

 protected:
  const std::string cmd_;  // "fix ID style", the prefix of every message
  RecordLists records_;

  // The most records one atom may carry (sizes the exchange and restart buffers).
  void set_records_per_atom(int most);
  // A restart block that is not whole records: ERROR (checked before check_restored).
  void restart_mismatch(int i) override;
};

}  // namespace dembridge::state
