// The test peer as MBDyn's `external modal` element, `type, all`, on a free modal body
// (free_modal_body_model.h), loose or tight coupling, as recorded with MBDyn 1.7.3: 07|5|M from the
// peer, 08; the kinematics are x, R (column-major), v, w of the modal node, then q[M], q'[M]; the
// loads F, M (global, about the node), then p[M]. The initial derivatives are skipped (MBDyn
// cannot solve them for a free modal node; the recorded models set `derivatives tolerance: 1e10`).
// Loose: 6|t0, its answer unused; per step 6|prediction, the answer kept for the step. Tight:
// nothing at t0; per step 2|prediction, then 2|iterate after every Newton update until the peer
// answers 6, MBDyn then iterates on silently. 5 after the last step. Independent of coupling/protocol.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "modal_fem_file.h"
#include "testpeer_socket.h"

namespace dembridge::mbdyn::testpeer {

struct FreeModalBodyPeerSetup {
  SocketPlace place;
  ModalFemData fem;
  int origin = -1;  // FEM node on the modal node (`origin node`), -1: the FEM frame's origin
  V3 x0{}, v0{}, w0{};
  std::vector<double> q0, qdot0;  // default: the FEM file's records 3 and 4
  double tolerance = 1e-9;        // MBDyn's `tolerance`
  int max_iterations = 20;        // MBDyn's `max iterations`
  bool tight = false;
  int steps = 10;
  double dt = 1e-3;
  double accept_timeout_s = 30, io_timeout_s = 30;
  std::string trajectory;  // if set: t, x, R (row by row), v, w, q, q', q'' after every step
  std::function<void()> on_listening;
};

struct FreeModalBodyPeerOutcome {
  int exit_status = 1;  // MBDyn's: 0 completed, 1 error, 2 interrupted
  std::string log;
  int kinematics_sent = 0;
};

FreeModalBodyPeerOutcome run_free_modal_body_test_peer(const FreeModalBodyPeerSetup& setup);

}  // namespace dembridge::mbdyn::testpeer
