// The test peer as MBDyn's `external modal` element with `type, modal` on a clamped modal node (a
// cantilevered flexible body): per mode M q'' + C q' + K q = p (diagonal, MBDyn's modal equations
// with the node fixed and no gravity), integrated by crank nicolson on the states (q, q'), as the
// recorded MBDyn 1.7.3 modal runs satisfy (q_k - q_k-1 = T/2 (q'_k-1 + q'_k), the same for q').
// Sequence as recorded (loose): 07|1|M from the peer, 08; 6|q0,q'0 read by the initial derivatives
// (q''0 from its answer); at every step 6|q,q' of the last converged step (MBDyn sends the modal
// joint's states before its predictor updates them), the answer p[M] frozen for the step; 5 after
// the last step. Tight (`tight`): the t0 exchange with command 2, then per step iterates 2|q,q',
// each solved by crank nicolson with the last loads answered (the first with the previous step's),
// until the peer answers 6; the step is then solved with those loads. --save-state/--resume keep
// the converged state of the last step solved (text, 17 digits), so a resumed run continues with
// the next step bit for bit. Independent of coupling/protocol.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "testpeer_socket.h"

namespace dembridge::mbdyn::testpeer {

struct ModalPeerSetup {
  SocketPlace place;
  std::vector<double> mass, damping, stiffness;  // one per mode (the FEM file's diagonal)
  std::vector<double> q0, qdot0;                 // initial modal coordinates (default 0)
  bool tight = false;
  int max_iterations = 50;       // tight: exchanges per step before giving up (status 1)
  std::string save_state;        // at the end: the state after the last step solved with the peer's loads
  std::string resume_state;      // continue from such a state: no t0 exchange, the next step first
  std::string loads_log;         // one line per answer: index, command, p
  int steps = 10;
  double dt = 1e-3;
  double accept_timeout_s = 30, io_timeout_s = 30;
  std::function<void()> on_listening;  // called once listening
};

struct ModalSample {
  double t = 0;
  std::vector<double> q, qdot, qddot, p;  // converged state at t, and the p it was solved with
};

struct ModalPeerOutcome {
  int exit_status = 1;  // MBDyn's: 0 completed, 1 error, 2 interrupted
  std::string log;
  int kinematics_sent = 0;
  std::vector<ModalSample> trajectory;  // t0 and every step
};

ModalPeerOutcome run_modal_test_peer(const ModalPeerSetup& setup);

}  // namespace dembridge::mbdyn::testpeer
