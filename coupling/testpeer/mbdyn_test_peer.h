// A stand-in for MBDyn's `external structural` element over a socket, byte for byte as the spec
// describes it (server or client role, negotiation checks, the t0 exchange, loose / tight / none
// coupling, MBDyn's error reactions), driving the OscillatorModel. Fault injection covers the
// robustness cases of the peer-side library. Independent of coupling/protocol.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "oscillator_model.h"
#include "testpeer_files.h"
#include "testpeer_socket.h"
#include "testpeer_wire.h"

namespace dembridge::mbdyn::testpeer {

enum class CouplingMode { Loose, Tight, None };

// What the test peer does wrong, at kinematics message number fault_message (0 = t0 message).
enum class Fault {
  None,
  GarbageCommand,         // command byte 66 instead of 2/6, then waits for the peer's 5
  ShortPayloadThenClose,  // command + half the payload, then closes
  ShortPayloadThenStall,  // command + half the payload, then waits for the peer's 5
  NanInKinematics,        // velocity y of the last node is NaN, then waits for the peer's 5
  DieMidRun,              // closes the socket (RST on TCP) instead of sending
};

struct PeerSetup {
  SocketPlace place;
  bool mbdyn_creates_socket = true;  // `create, yes`: the test peer listens
  ElementShape shape;
  std::vector<std::uint32_t> node_labels;  // default 10, 20, 30, ...
  std::uint32_t reference_label = 1;
  CouplingMode coupling = CouplingMode::Loose;
  int steps = 10;
  double dt = 1e-3;
  OscillatorParameters model;  // initial states default to a fixed, non-trivial set; offsets 0
  int max_iterations = 20;             // MBDyn `max iterations` (Newton iterations per step)
  int derivatives_max_iterations = 10;  // MBDyn `derivatives max iterations` (spec T1)
  double tolerance = 1e-9;              // MBDyn `tolerance` (residual norm)
  double derivatives_tolerance = 1e-6;  // MBDyn `derivatives tolerance`
  double accept_timeout_s = 10.0;
  double io_timeout_s = 10.0;  // the real MBDyn waits forever; tests must not
  Fault fault = Fault::None;
  int fault_message = 1;
  std::string kinematics_log;  // if set: one line per kinematics message sent (see main.cpp)
  std::string loads_log;       // if set: one line per loads answer received (see main.cpp)
  std::function<void(int port)> on_listening;  // called once listening (TCP port if any)
  // File communicator instead of the socket (loose, `send after predict, no`): when files.in_path
  // is set. OUT at t0, IN read by the derivatives, OUT again after them, then per step: IN read
  // at the step's start, OUT of the converged state (the recorded real run's sequence).
  PeerFiles files;
  // Across a LAMMPS restart (socket, loose or tight): save_state names the file the peer writes
  // when it ends, its state after the last step it solved with the peer's loads; resume_state a
  // file to continue from: no start-up (t0) exchange, the first message is the next step's.
  std::string save_state, resume_state;
};

struct PeerSample {
  double t = 0;
  std::vector<BodyState> bodies;
};

struct PeerOutcome {
  int exit_status = 1;  // MBDyn's: 0 completed, 1 error, 2 interrupted (spec §6)
  std::string log;      // MBDyn-like reason for the end
  std::uint32_t received_flags = 0;
  std::uint32_t received_nodes = 0;
  int kinematics_sent = 0;
  std::vector<std::uint8_t> answers;  // command bytes received from the peer, in order
  std::vector<PeerSample> trajectory;  // converged states at t0 and after every step
  LoadsMessage last_loads;             // as received (reference-node frame if any)
  bool abort_received_after_fault = false;
};

PeerOutcome run_mbdyn_test_peer(const PeerSetup& setup);

// Default initial states used when setup.model.initial is empty.
std::vector<BodyState> default_initial_states(std::uint32_t nodes);
// Fixed reference node pose used with shape.reference_node (static, tilted, off-origin).
NodeState reference_node_state(std::uint32_t label);

}  // namespace dembridge::mbdyn::testpeer
