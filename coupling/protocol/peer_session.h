// The peer's side of one `external structural` coupling: connection, negotiation and the
// message sequence of loose, tight or none coupling (spec §5), with the step bookkeeping the
// protocol itself does not carry (spec P7). Only MPI rank 0 should own one.
#pragma once

#include <cstdint>
#include <vector>

#include "negotiation.h"
#include "nodal_config.h"
#include "nodal_message.h"
#include "socket_transport.h"

namespace dembridge::mbdyn {

// `coupling, ...` of the MBDyn element (spec §5). Staggered is not supported (spec §5.3).
enum class Coupling { Loose, Tight, None };
std::string coupling_name(Coupling c);

// Who creates the socket: MBDyn (`create, yes`, we connect: recommended) or we (`create, no`).
enum class SocketRole { MbdynCreates, PeerCreates };

struct SessionOptions {
  Endpoint endpoint;
  SocketRole role = SocketRole::MbdynCreates;
  NodalConfig nodal;
  Coupling coupling = Coupling::Loose;
  double connect_timeout_s = 60.0;  // connect retries / accept wait; < 0 waits forever
  double io_timeout_s = 300.0;      // each message read or write; < 0 waits forever
  double abort_timeout_s = 1.0;     // how long abort() tries to deliver its 5
};

// What receive() returned.
struct Received {
  enum class Kind { Kinematics, EndOfSimulation };
  Kind kind = Kind::EndOfSimulation;
  std::uint64_t message_index = 0;  // 0 = the t0 message
  std::uint64_t step = 0;           // 0 = start-up (t0) exchange(s); k = MBDyn step k
  std::uint32_t iteration = 0;      // exchange within the step (tight), 0 for the prediction
  bool starts_new_step = false;     // first message after our converged answer (spec §5.2)
  bool is_kinematics() const { return kind == Kind::Kinematics; }
};

class PeerSession {
 public:
  // Connects or listens according to options.role, then negotiates.
  static PeerSession open(const SessionOptions& options);
  // `create, no` with a listener made before MBDyn was launched.
  static PeerSession accept(SocketListener& listener, const SessionOptions& options);
  // Negotiates over an already connected transport, in the direction options.role implies.
  PeerSession(SocketTransport transport, const SessionOptions& options);

  PeerSession(PeerSession&&) noexcept;
  PeerSession& operator=(PeerSession&&) = delete;
  PeerSession(const PeerSession&) = delete;
  PeerSession& operator=(const PeerSession&) = delete;
  // Sends 5 (best effort) if the simulation did not end normally: a clean abort.
  ~PeerSession();

  // Blocks (io_timeout_s) for MBDyn's next message. Kinematics are in kinematics(). After a 5
  // the session is finished. Unknown commands, wrong lengths, non-finite values and timeouts
  // send 5 to MBDyn and throw; EOF/reset without a 5 throws PeerClosedError.
  Received receive();
  const Kinematics& kinematics() const { return kinematics_; }
  // The raw payload of the last kinematics message (host byte order, spec §2): MPI ranks can
  // receive it by broadcast and call decode_kinematics(config(), command, ...) themselves (P5).
  const std::vector<std::uint8_t>& raw_payload() const { return payload_; }

  // Answers the last kinematics. converged=true sends 6 (mandatory in loose, spec P9);
  // converged=false sends 2 (tight only: MBDyn sends another iterate). Labels are echoed
  // automatically from the last kinematics (spec P10).
  void send_loads(const Loads& loads, bool converged);
  // Answers 4: converged, MBDyn keeps the loads it already has. No payload.
  void send_converged_keep_loads();
  // Answers 5 instead of loads: MBDyn finishes this step, sends 5 and exits with status 2
  // (spec §6, P13). Afterwards receive() skips to the end and returns EndOfSimulation.
  void request_stop();
  // Error path: sends 5 if possible and closes; never throws.
  void abort() noexcept;
  // A coupling continued by a new process (a peer restarted from a restart file, and an MBDyn
  // that continues the same coupling): before the first receive(), the session counts as having
  // answered MBDyn step `step` converged, so the next message is step + 1, not a start-up (t0).
  void continue_after_step(std::uint64_t step);

  bool finished() const { return state_ == State::Finished; }
  const NodalConfig& config() const { return options_.nodal; }
  const SessionOptions& options() const { return options_; }
  std::uint64_t messages_received() const { return messages_received_; }

 private:
  enum class State { AwaitingKinematics, AwaitingAnswer, StopRequested, Finished, Failed };
  Received receive_message();
  Received finish();
  void write_answer(const std::vector<std::uint8_t>& bytes, bool converged);
  void require_answer_allowed(const char* what) const;

  SessionOptions options_;
  SocketTransport transport_;
  State state_ = State::AwaitingKinematics;
  Kinematics kinematics_;
  std::vector<std::uint8_t> payload_;
  std::vector<std::uint8_t> answer_;  // the last loads message sent, reused
  std::string payload_what_;          // "kinematics payload of N bytes (...)", for read errors
  std::uint64_t messages_received_ = 0;
  std::uint64_t step_ = 0;
  std::uint32_t iteration_ = 0;
  bool last_answer_converged_ = false;
  bool continued_ = false;  // continue_after_step(): no start-up message in this session
};

}  // namespace dembridge::mbdyn
