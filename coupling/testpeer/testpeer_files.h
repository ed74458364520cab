// MBDyn's file communicator as the test peer plays it (MBDyn's side, `"IN", unlink, "OUT",
// no clobber`): write OUT as text (`# regular nodes`, one line per node: [label] x y z [R row by
// row] vx vy vz [wx wy wz], `%.<precision>e`) through OUT.tmp and a rename, once the peer removed
// the previous OUT; read IN ([label] Fx Fy Fz [Mx My Mz] per node), then delete it. Written from
// the MBDyn manual and the recorded run, independently of coupling/protocol.
#pragma once

#include <string>
#include <vector>

#include "testpeer_wire.h"

namespace dembridge::mbdyn::testpeer {

struct PeerFiles {
  std::string in_path, out_path;
  int precision = 16;
  double sleep_s = 0.001;
  double timeout_s = 10;
};

// Orientation none or matrix only. Returns "" or why it failed (a timeout, an I/O error).
std::string write_out_file(const PeerFiles& f, const ElementShape& shape, const std::vector<NodeState>& nodes);
// Waits for IN, reads and deletes it. Returns "" or why it failed (timeout, malformed line).
std::string read_in_file(const PeerFiles& f, const ElementShape& shape, LoadsMessage& loads);

}  // namespace dembridge::mbdyn::testpeer
