// The test peer as MBDyn's `external structural` element with `reference node` on free rigid
// bodies (free_bodies_model.h): the reference node and the N points are dynamic nodes with a body
// each, `labels, yes`, `sorted, no`, `orientation matrix`, `use reference node forces, yes,
// rotate reference node forces, yes`, loose or tight coupling. Sequence as recorded: 07|flags|N
// from the peer, 08; loose: 6|kinematics at t0, read by the initial derivatives; per step
// 6|prediction, the answer frozen (in the reference frame) for the step; tight: 2|t0 (the
// derivatives iterate), then per step 2|prediction and 2|iterate after every Newton update until
// the peer answers 6 (free_bodies_peer.cpp); 5 after the last step.
// MBDyn's use of an answer (checked on the recorded run): point k gets R_r F~ and R_r M~ of the
// slot whose index is the position, in the element's list, of the label in slot k (MBDyn's
// `sorted, no` mapping: right for the received order); the reference node gets R_r F0 - sum f and
// R_r M0 - sum (m + (x - x_r) x f). Independent of coupling/protocol.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "free_bodies_model.h"
#include "testpeer_socket.h"

namespace dembridge::mbdyn::testpeer {

struct FreeBodiesPeerSetup {
  SocketPlace place;
  FreeBody reference;            // the reference node's body (initial state)
  std::vector<FreeBody> points;  // the points' bodies, in the element's order
  std::uint32_t reference_label = 10;
  std::vector<std::uint32_t> labels;  // the points' labels, in the element's order
  V3 gravity{0, 0, 0};
  double derivatives_coefficient = 1e-6;
  double tolerance = 1e-9;  // MBDyn's `tolerance`
  int max_iterations = 20;  // MBDyn's `max iterations`
  bool tight = false;       // MBDyn's `coupling, tight` (else loose)
  int steps = 10;
  double dt = 1e-3;
  double accept_timeout_s = 30, io_timeout_s = 30;
  std::string trajectory;  // if set: t, then per body (reference first) x R(row by row) v w
  std::function<void()> on_listening;
};

struct FreeBodiesPeerOutcome {
  int exit_status = 1;  // MBDyn's: 0 completed, 1 error, 2 interrupted
  std::string log;
  int kinematics_sent = 0;
};

FreeBodiesPeerOutcome run_free_bodies_test_peer(const FreeBodiesPeerSetup& setup);

}  // namespace dembridge::mbdyn::testpeer
