#include "peer_session.h"

#include <stdexcept>
#include <utility>

#include "protocol_error.h"

namespace dembridge::mbdyn {

namespace {
// Kinematics (2, 6) carry a payload; 5 and invalid codes do not.
bool carries_kinematics(std::uint8_t cmd) {
  return cmd == static_cast<std::uint8_t>(Command::RegularData) ||
         cmd == static_cast<std::uint8_t>(Command::RegularDataAndGotoNextStep);
}
}  // namespace

std::string coupling_name(Coupling c) {
  switch (c) {
    case Coupling::Loose: return "loose";
    case Coupling::Tight: return "tight";
    case Coupling::None: return "none";
  }
  return "unknown";
}

PeerSession PeerSession::open(const SessionOptions& options) {
  if (options.role == SocketRole::PeerCreates) {
    SocketListener listener(options.endpoint);
    return accept(listener, options);
  }
  return PeerSession(SocketTransport::connect(options.endpoint, options.connect_timeout_s), options);
}

PeerSession PeerSession::accept(SocketListener& listener, const SessionOptions& options) {
  return PeerSession(listener.accept(options.connect_timeout_s), options);
}

PeerSession::PeerSession(SocketTransport transport, const SessionOptions& options)
    : options_(options), transport_(std::move(transport)) {
  try {
    if (options_.role == SocketRole::MbdynCreates)
      negotiate_as_client(transport_, options_.nodal, options_.io_timeout_s);
    else
      accept_negotiation_as_server(transport_, options_.nodal, options_.io_timeout_s);
  } catch (...) {
    state_ = State::Failed;
    transport_.close();
    throw;
  }
  transport_.defer_consumption();  // Unix: MBDyn is not woken by our receives (socket_transport.h)
  payload_.resize(options_.nodal.kinematics_payload_bytes());
  // formatted once: read_message takes it on every message (it is used only in error messages)
  payload_what_ = "kinematics payload of " + std::to_string(payload_.size()) + " bytes (" + options_.nodal.describe() + ")";
}

PeerSession::PeerSession(PeerSession&& o) noexcept
    : options_(std::move(o.options_)),
      transport_(std::move(o.transport_)),
      state_(o.state_),
      kinematics_(std::move(o.kinematics_)),
      payload_(std::move(o.payload_)),
      answer_(std::move(o.answer_)),
      payload_what_(std::move(o.payload_what_)),
      messages_received_(o.messages_received_),
      step_(o.step_),
      iteration_(o.iteration_),
      last_answer_converged_(o.last_answer_converged_),
      continued_(o.continued_) {
  o.state_ = State::Failed;
}

PeerSession::~PeerSession() {
  if (state_ != State::Finished) abort();
}

void PeerSession::abort() noexcept {
  if (transport_.is_open())
    transport_.try_write_byte(static_cast<std::uint8_t>(Command::Abort), options_.abort_timeout_s);
  transport_.close();
  if (state_ != State::Finished) state_ = State::Failed;
}

Received PeerSession::finish() {
  state_ = State::Finished;
  transport_.close();
  Received r;
  r.kind = Received::Kind::EndOfSimulation;
  r.message_index = messages_received_;
  r.step = step_;
  return r;
}

Received PeerSession::receive() {
  if (state_ == State::Finished || state_ == State::Failed)
    throw std::logic_error("PeerSession::receive: the session has ended");
  if (state_ == State::AwaitingAnswer && options_.coupling != Coupling::None)
    throw std::logic_error("PeerSession::receive: answer the previous kinematics first (" +
                           coupling_name(options_.coupling) + " coupling, spec §5)");
  if (state_ == State::StopRequested) {
    // MBDyn finishes its step and sends 5; EOF or RST are also a normal end here (spec P13).
    try {
      for (;;) {
        std::uint8_t cmd = 0;
        transport_.read_exact(&cmd, 1, options_.io_timeout_s, "MBDyn's final 5 after our stop request");
        if (cmd == static_cast<std::uint8_t>(Command::Abort)) return finish();
        if (cmd != 2 && cmd != 6) break;
        transport_.read_exact(payload_.data(), payload_.size(), options_.io_timeout_s, "kinematics payload");
      }
    } catch (const PeerClosedError&) {
      return finish();
    } catch (...) {
      abort();
      throw;
    }
    abort();
    throw MalformedMessageError("after our stop request: expected command 5 from MBDyn, received another code");
  }
  try {
    return receive_message();
  } catch (const PeerClosedError&) {
    transport_.close();
    state_ = State::Failed;
    throw;
  } catch (...) {
    abort();  // spec §6/P4: tell MBDyn to stop, as MBDyn itself does on a bad code
    throw;
  }
}

Received PeerSession::receive_message() {
  std::uint8_t cmd = 0;  // 0 is no command: still 0 after a throw means nothing arrived
  try {
    static const std::string what = "a command byte (2, 5 or 6)";  // no string built per message
    // Command and payload in as few recv calls as possible (one when they arrive together), into
    // one buffer: a recvmsg scattering straight into kinematics_'s six arrays cost ~1 us more
    // of kernel time than the copies it saves (issue 12, P5).
    transport_.read_message(cmd, payload_.data(), payload_.size(), carries_kinematics, options_.io_timeout_s, what,
                            payload_what_);
  } catch (const PeerClosedError& e) {
    if (cmd != 0) throw;
    throw PeerClosedError(std::string(e.what()) +
                          "; MBDyn ended without sending 5 (end of simulation): it crashed or was killed");
  }
  if (cmd == static_cast<std::uint8_t>(Command::Abort)) return finish();

  const bool regular = cmd == static_cast<std::uint8_t>(Command::RegularData);
  const bool regular_and_next = cmd == static_cast<std::uint8_t>(Command::RegularDataAndGotoNextStep);
  if (!regular && !regular_and_next)
    throw MalformedMessageError("MBDyn sent an invalid command: expected 2, 5 or 6, received " +
                                command_name(cmd));
  // MBDyn sends 6 in loose and none coupling and 2 in tight, including at t0 (spec §5).
  const bool tight = options_.coupling == Coupling::Tight;
  if (tight != regular)
    throw MalformedMessageError(
        "MBDyn sent command " + command_name(cmd) + " but " + coupling_name(options_.coupling) +
        " coupling expects " + (tight ? "2" : "6") +
        ": the `coupling` of the MBDyn element and of this peer disagree");

  decode_kinematics_into(options_.nodal, static_cast<Command>(cmd), payload_.data(), payload_.size(), kinematics_);

  Received r;
  r.kind = Received::Kind::Kinematics;
  r.message_index = messages_received_;
  if (messages_received_ == 0 && !continued_) {
    step_ = 0;
    iteration_ = 0;
    r.starts_new_step = true;
  } else if (options_.coupling == Coupling::None || last_answer_converged_) {
    ++step_;
    iteration_ = 0;
    r.starts_new_step = true;
  } else {
    ++iteration_;  // tight: MBDyn's next iterate of the same step
  }
  r.step = step_;
  r.iteration = iteration_;
  ++messages_received_;
  last_answer_converged_ = false;
  state_ = State::AwaitingAnswer;
  return r;
}

void PeerSession::continue_after_step(std::uint64_t step) {
  if (messages_received_ != 0)
    throw std::logic_error("PeerSession::continue_after_step: called after the first message");
  continued_ = true;
  step_ = step;
  iteration_ = 0;
  last_answer_converged_ = true;
}

void PeerSession::require_answer_allowed(const char* what) const {
  if (options_.coupling == Coupling::None)
    throw std::logic_error(std::string("PeerSession::") + what +
                           ": with `coupling, none` MBDyn never reads; the peer must not answer (spec §5.3)");
  if (state_ != State::AwaitingAnswer)
    throw std::logic_error(std::string("PeerSession::") + what +
                           ": expected to answer received kinematics, but no answer is pending");
}

namespace {
// "the answer <command>" for write errors, formatted once per command code rather than per message.
const std::string& answer_text(std::uint8_t cmd) {
  static const std::string t2 = "the answer " + command_name(2), t5 = "the answer " + command_name(5),
                           t6 = "the answer " + command_name(6);
  thread_local std::string other;
  if (cmd == 2) return t2;
  if (cmd == 5) return t5;
  if (cmd == 6) return t6;
  other = "the answer " + command_name(cmd);
  return other;
}
}  // namespace

void PeerSession::write_answer(const std::vector<std::uint8_t>& bytes, bool converged) {
  try {
    // One write per message: MBDyn reads the payload with a single recv (spec P2). One buffer and
    // send(): a sendmsg gathering from the loads arrays cost ~0.5 us more than the copy it saves.
    transport_.write_all(bytes.data(), bytes.size(), options_.io_timeout_s, answer_text(bytes[0]));
  } catch (const PeerClosedError&) {
    transport_.close();
    state_ = State::Failed;
    throw;
  } catch (...) {
    abort();
    throw;
  }
  last_answer_converged_ = converged;
  state_ = State::AwaitingKinematics;
}

void PeerSession::send_loads(const Loads& loads, bool converged) {
  require_answer_allowed("send_loads");
  if (options_.coupling == Coupling::Loose && !converged)
    throw std::logic_error(
        "PeerSession::send_loads: loose coupling must answer 6 (converged); answering 2 "
        "desynchronises MBDyn (spec §5.1, P9)");
  const Command cmd = converged ? Command::RegularDataAndGotoNextStep : Command::RegularData;
  // With labels, exactly the received labels, same order (spec P10); reused buffer: no allocation
  // per message, no copy of loads.
  encode_loads_into(options_.nodal, cmd, loads, kinematics_.labels, &kinematics_.reference.label, answer_);
  write_answer(answer_, converged);
}

void PeerSession::send_converged_keep_loads() {
  require_answer_allowed("send_converged_keep_loads");
  write_answer({static_cast<std::uint8_t>(Command::GotoNextStep)}, true);
}

void PeerSession::request_stop() {
  require_answer_allowed("request_stop");
  write_answer({static_cast<std::uint8_t>(Command::Abort)}, true);
  state_ = State::StopRequested;
}

}  // namespace dembridge::mbdyn
