// The test peer's state across a LAMMPS restart (mbdyn_testpeer --save-state / --resume): the
// converged state of the last MBDyn step the peer solved with the loads it was answered, and the
// state one step before (the two-step method needs it), as text at 17 significant digits, which
// reads back to the same doubles. A resumed peer continues with the next step's prediction, so
// the peer's trajectory and messages are those of the unbroken run bit for bit.
#pragma once

#include <string>
#include <vector>

#include "oscillator_model.h"

namespace dembridge::mbdyn::testpeer {

struct PeerState {
  int step = 0;                     // the last step solved (0: the initial derivatives only)
  std::vector<BodyState> state;     // converged state at step
  std::vector<BodyState> older;     // at step - 1 (empty at step 0)
};

// Returns "" or why it failed.
std::string write_peer_state(const std::string& path, const PeerState& s);
std::string read_peer_state(const std::string& path, std::size_t nodes, PeerState& s);

}  // namespace dembridge::mbdyn::testpeer
