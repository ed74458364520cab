#include "mbdyn_test_peer.h"
#include "peer_state_file.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <limits>
#include <sstream>

namespace dembridge::mbdyn::testpeer {

namespace {

// Ends the run the way MBDyn would: exit status, log line, and whether to send 5 first.
struct RunEnds {
  int status;
  std::string why;
  bool send_abort;
};

struct Answer {
  std::uint8_t cmd = 0;
  NodeLoads loads;  // global force, z moment about the node
};

class PeerRun {
 public:
  explicit PeerRun(const PeerSetup& s) : s_(s), model_(with_defaults(s)) {
    if (s_.node_labels.empty())
      for (std::uint32_t i = 0; i < s_.shape.nodes; ++i) s_.node_labels.push_back(10 * (i + 1));
    ref_ = reference_node_state(s_.reference_label);
    loads_.force.assign(s_.shape.nodes, V3{0, 0, 0});
    loads_.moment_z.assign(s_.shape.nodes, 0.0);
  }

  PeerOutcome run() {
    try {
      if (!s_.files.in_path.empty()) {
        run_files();
        finish({0, "End of simulation", false});
        return out_;
      }
      if (!s_.resume_state.empty()) resume();
      connect();
      negotiate();
      switch (s_.coupling) {
        case CouplingMode::Loose: run_loose(); break;
        case CouplingMode::Tight: run_tight(); break;
        case CouplingMode::None: run_none(); break;
      }
      finish({0, "End of simulation", true});
    } catch (const RunEnds& e) {
      finish(e);
    }
    return out_;
  }

 private:
  static OscillatorParameters with_defaults(const PeerSetup& s) {
    OscillatorParameters p = s.model;
    if (p.initial.empty()) p.initial = default_initial_states(s.shape.nodes);
    if (p.tilt.empty())
      for (std::uint32_t i = 0; i < s.shape.nodes; ++i) p.tilt.push_back(0.3 * (i + 1));
    return p;
  }

  bool rotates() const { return s_.shape.orientation != Orientation::None; }

  void finish(const RunEnds& e) {
    if (e.send_abort && sock_.is_open()) {
      const std::uint8_t five = 5;
      sock_.send_bytes(&five, 1);
    }
    sock_.close_now();
    out_.exit_status = e.status;
    out_.log = e.why;
    if (!s_.save_state.empty() && have_done_) {
      const std::string err = write_peer_state(s_.save_state, done_);
      if (!err.empty()) out_.log += "; " + err;
    }
  }

  // --resume: the state of the last step solved; the run goes on with the next step.
  void resume() {
    PeerState st;
    const std::string err = read_peer_state(s_.resume_state, s_.shape.nodes, st);
    if (!err.empty()) throw RunEnds{1, err, false};
    model_.restore(st.state, st.older);
    first_step_ = st.step + 1;
    resumed_ = true;
    record(st.step * s_.dt);
    solved(st.step);
  }

  // The state after step k, solved with the peer's loads (what --save-state keeps).
  void solved(int k) {
    done_.step = k;
    done_.state = model_.state();
    done_.older = model_.older();
    have_done_ = true;
  }

  void connect() {
    std::string err;
    if (s_.mbdyn_creates_socket) {
      int port = -1;
      err = sock_.listen_on(s_.place, &port);
      if (err.empty() && s_.on_listening) s_.on_listening(port);
      if (err.empty()) err = sock_.accept_client(s_.accept_timeout_s);
    } else {
      err = sock_.connect_to(s_.place, s_.accept_timeout_s);
    }
    if (!err.empty()) throw RunEnds{1, err, false};
    sock_.set_io_timeout(s_.io_timeout_s);
  }

  void negotiate() {
    const std::uint32_t flags = negotiation_flags(s_.shape);
    if (!s_.mbdyn_creates_socket) {
      // MBDyn as client sends its request and then its own 8 without reading (spec §3).
      std::uint8_t req[9];
      req[0] = 7;
      std::memcpy(req + 1, &flags, 4);
      std::memcpy(req + 5, &s_.shape.nodes, 4);
      const std::uint8_t ok = 8;
      if (!sock_.send_bytes(req, 9) || !sock_.send_bytes(&ok, 1))
        throw RunEnds{1, "negotiation: send failed", false};
      out_.received_flags = flags;
      out_.received_nodes = s_.shape.nodes;
      return;
    }
    std::uint8_t req[9];
    const std::size_t got = sock_.receive_all(req, 9);
    if (got < 9)
      throw RunEnds{1, "negotiation: recv() got " + std::to_string(got) + " of 9 bytes", false};
    std::uint32_t rflags, rnodes;
    std::memcpy(&rflags, req + 1, 4);
    std::memcpy(&rnodes, req + 5, 4);
    out_.received_flags = rflags;
    out_.received_nodes = rnodes;
    if (req[0] != 7)
      throw RunEnds{1, "negotiation: expected command 7, got " + std::to_string(req[0]), true};
    std::ostringstream why;
    auto compare = [&](const char* what, std::uint32_t local, std::uint32_t remote) {
      if (local != remote) why << what << " mismatch (local=" << local << ", remote=" << remote << ")";
    };
    // The same checks, in the same order, as MBDyn's negotiation response; reference-node
    // rotation bits are ignored by external structural.
    if (!(rflags & 0x2)) why << "nodal flag missing";
    else compare("reference node", flags & 0x4, rflags & 0x4);
    if (why.str().empty()) compare("labels", flags & 0x10, rflags & 0x10);
    if (why.str().empty()) compare("accelerations", flags & 0x8, rflags & 0x8);
    if (why.str().empty()) compare("orientation output", flags & 0xF00, rflags & 0xF00);
    if (why.str().empty()) compare("node count", s_.shape.nodes, rnodes);
    if (!why.str().empty())
      throw RunEnds{1, "StructExtForce: negotiation response failed: " + why.str(), true};
    const std::uint8_t ok = 8;
    sock_.send_bytes(&ok, 1);
  }

  std::vector<NodeState> wire_nodes(const std::vector<BodyState>& bodies) const {
    std::vector<NodeState> nodes;
    const Mat3 RrT = transpose(ref_.R);
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      NodeState n = model_.point_of(i, bodies[i], s_.node_labels[i]);
      if (s_.shape.reference_node) {
        // Relative to the (static) reference node, in its frame (spec §4.3).
        V3 dx;
        for (int k = 0; k < 3; ++k) dx[k] = n.x[k] - ref_.x[k];
        n.x = rotate_vector(RrT, dx);
        n.R = multiply(RrT, n.R);
        n.v = rotate_vector(RrT, n.v);
        n.w = rotate_vector(RrT, n.w);
        n.a = rotate_vector(RrT, n.a);
        n.wdot = rotate_vector(RrT, n.wdot);
      }
      nodes.push_back(n);
    }
    return nodes;
  }

  void wait_for_abort_from_peer() {
    std::uint8_t b = 0;
    const long rc = sock_.receive_once(&b, 1);
    out_.abort_received_after_fault = rc == 1 && b == 5;
  }

  void send_kinematics(std::uint8_t cmd, const std::vector<BodyState>& bodies) {
    last_sent_ = bodies;
    std::vector<NodeState> nodes = wire_nodes(bodies);
    const bool faulty = s_.fault != Fault::None && out_.kinematics_sent == s_.fault_message;
    if (faulty && s_.fault == Fault::DieMidRun) {
      sock_.close_now();
      throw RunEnds{1, "fault injected: died before kinematics message " + std::to_string(s_.fault_message), false};
    }
    if (faulty && s_.fault == Fault::NanInKinematics && !nodes.empty())
      nodes.back().v[1] = std::numeric_limits<double>::quiet_NaN();
    const std::vector<std::uint8_t> payload = encode_kinematics_payload(s_.shape, ref_, nodes);
    if (!s_.kinematics_log.empty()) log_kinematics(cmd, bodies);
    if (faulty && s_.fault == Fault::GarbageCommand) cmd = 66;
    std::size_t length = payload.size();
    if (faulty && (s_.fault == Fault::ShortPayloadThenClose || s_.fault == Fault::ShortPayloadThenStall))
      length /= 2;
    bool sent;
    if (faulty) {
      // One send, so the peer's reaction cannot race with the rest of the faulty message.
      std::vector<std::uint8_t> message{cmd};
      message.insert(message.end(), payload.begin(), payload.begin() + static_cast<long>(length));
      sent = sock_.send_bytes(message.data(), message.size());
    } else {
      // MBDyn sends the command byte and the payload with separate send() calls (spec P3).
      sent = sock_.send_bytes(&cmd, 1) && sock_.send_bytes(payload.data(), length);
    }
    if (!sent) {
      // The peer may have answered 5 and closed while we were sending; keep what it said.
      std::uint8_t b = 0;
      if (sock_.receive_once(&b, 1) == 1) out_.answers.push_back(b);
      throw RunEnds{2, b == 5 ? "ExtSocketHandler: peer requested end of simulation (during send)"
                              : "send() to peer failed (SIGPIPE): peer gone", false};
    }
    ++out_.kinematics_sent;
    if (!faulty) return;
    if (s_.fault == Fault::ShortPayloadThenClose) {
      sock_.close_now();
      throw RunEnds{1, "fault injected: short payload then close", false};
    }
    wait_for_abort_from_peer();
    throw RunEnds{1, "fault injected at kinematics message " + std::to_string(s_.fault_message), false};
  }

  // message index, command, then per node (global frame, the point): x, R row by row, v, w
  void log_kinematics(std::uint8_t cmd, const std::vector<BodyState>& bodies) {
    if (!klog_) {
      klog_ = std::make_unique<std::ofstream>(s_.kinematics_log);
      klog_->precision(17);
    }
    *klog_ << out_.kinematics_sent << ' ' << int(cmd);
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const NodeState n = model_.point_of(i, bodies[i], s_.node_labels[i]);
      for (double v : n.x) *klog_ << ' ' << v;
      for (const auto& row : n.R)
        for (double v : row) *klog_ << ' ' << v;
      for (double v : n.v) *klog_ << ' ' << v;
      for (double v : n.w) *klog_ << ' ' << v;
    }
    *klog_ << '\n';
  }

  // answer index, command, then per point the force and the moment as received
  void log_loads(std::uint8_t cmd, const LoadsMessage& m) {
    if (!llog_) {
      llog_ = std::make_unique<std::ofstream>(s_.loads_log);
      llog_->precision(17);
    }
    *llog_ << out_.answers.size() - 1 << ' ' << int(cmd);
    for (std::size_t i = 0; i < m.force.size(); ++i) {
      for (double v : m.force[i]) *llog_ << ' ' << v;
      if (i < m.moment.size())
        for (double v : m.moment[i]) *llog_ << ' ' << v;
    }
    if (s_.shape.reference_node) {
      for (double v : m.ref_force) *llog_ << ' ' << v;
      for (double v : m.ref_moment) *llog_ << ' ' << v;
    }
    *llog_ << '\n';
  }

  Answer read_answer() {
    Answer a;
    std::uint8_t cmd = 0;
    const long rc = sock_.receive_once(&cmd, 1);
    if (rc == 0) throw RunEnds{2, "ExtSocketHandler: recv()=0 (expected 1)", false};
    if (rc < 0) throw RunEnds{1, "test peer: no command from the peer within the io timeout", true};
    a.cmd = cmd;
    out_.answers.push_back(cmd);
    if (cmd == 4 || cmd == 5) return a;
    if (cmd != 2 && cmd != 6)
      throw RunEnds{2, "ExtSocketHandler: received unknown code (" + std::to_string(cmd) + ")", true};
    // One recv() for the payload, as MBDyn 1.7.3 does (spec §6, P2): a peer that splits its
    // message into several writes fails here exactly as with the real MBDyn.
    const std::size_t want = loads_payload_size(s_.shape);
    std::vector<std::uint8_t> buf(want + 1);
    long got = want ? sock_.receive_once(buf.data(), want) : 0;
    if (got < 0) got = 0;
    if (static_cast<std::size_t>(got) != want)
      throw RunEnds{1, "StructExtForce: recv() failed (got " + std::to_string(got) + " of " +
                           std::to_string(want) + " bytes)", true};
    LoadsMessage m = decode_loads_payload(s_.shape, buf.data(), want);
    if (!s_.loads_log.empty()) log_loads(cmd, m);
    if (s_.shape.labels) {
      if (s_.shape.reference_node && m.ref_label != s_.reference_label)
        throw RunEnds{1, "invalid reference node label (wanted " + std::to_string(s_.reference_label) +
                             ", got " + std::to_string(m.ref_label) + ")", true};
      for (std::size_t i = 0; i < m.labels.size(); ++i)
        if (m.labels[i] != s_.node_labels[i])
          throw RunEnds{1, "invalid " + std::to_string(i) + "-th label " + std::to_string(m.labels[i]), true};
    }
    for (std::size_t i = 0; i < m.force.size(); ++i) {
      V3 f = m.force[i], mo = m.moment[i];
      if (s_.shape.reference_node) {
        f = rotate_vector(ref_.R, f);  // point loads are in the reference node's frame (spec §4.3)
        mo = rotate_vector(ref_.R, mo);
      }
      a.loads.force.push_back(f);
      // Without orientation there are no moments at all (spec §4.4).
      a.loads.moment_z.push_back(rotates() ? model_.node_moment_z(i, last_sent_[i], f, mo) : 0.0);
    }
    out_.last_loads = m;
    return a;
  }

  void record(double t) { out_.trajectory.push_back({t, model_.state()}); }

  // The peer asked to stop (5): keep the loads, finish the step, send 5, exit 2 (spec §6).
  [[noreturn]] void peer_requested_end(int step) {
    if (step > 0) {
      model_.accept(model_.solve(s_.dt, loads_));
      record(step * s_.dt);
    }
    throw RunEnds{2, "ExtSocketHandler: peer requested end of simulation; MBDyn was interrupted", true};
  }

  // Reads an answer; returns true when the peer declared convergence (6 or 4). 4 keeps the loads.
  bool read_and_take(int step, bool loose) {
    const Answer a = read_answer();
    if (a.cmd == 5) peer_requested_end(step);
    if (loose && a.cmd == 2)
      throw RunEnds{1, "peer answered 2 in loose coupling: the stream desynchronises (spec 5.1)", true};
    if (a.cmd == 2 || a.cmd == 6) loads_ = a.loads;
    return a.cmd == 6 || a.cmd == 4;
  }

  // MBDyn's Newton loop for one step once the loads are frozen (loose) or after the peer declared
  // convergence (tight): the predicted state stands if its residual is within tolerance,
  // otherwise one correction solves the linear step for these loads.
  std::vector<BodyState> converge_with_frozen_loads(const std::vector<BodyState>& iterate) const {
    if (model_.residual_norm(iterate, loads_) <= s_.tolerance) return iterate;
    return model_.solve(s_.dt, loads_);
  }

  void run_loose() {
    if (!resumed_) {
      send_kinematics(6, model_.state());  // start-up: initial state (spec §5)
      read_and_take(0, true);             // the initial-derivatives solve reads one load message
      if (model_.residual_norm(model_.state(), loads_, false) > s_.derivatives_tolerance)
        model_.derivatives_update(loads_, s_.dt);
      record(0.0);
      solved(0);
    }
    for (int k = first_step_; k <= s_.steps; ++k) {
      const std::vector<BodyState> predicted = model_.predict(s_.dt);
      send_kinematics(6, predicted);
      read_and_take(k, true);
      model_.accept(converge_with_frozen_loads(predicted));
      record(k * s_.dt);
      solved(k);
    }
  }

  // MBDyn reads loads in the residual of every Newton iteration that follows a kinematics message,
  // and sends kinematics after every update until the peer has answered 6 or 4 (spec §5.2).
  void run_tight() {
    // Initial derivatives: iterates (and so exchanges) only if the residual at t0 without the
    // peer's loads is not already within tolerance (spec T2; the first message then is step 1's).
    bool outstanding = false, peer_converged = false;
    for (int it = 0; !resumed_; ++it) {
      if (outstanding) {
        peer_converged = read_and_take(0, false) || peer_converged;
        outstanding = false;
      }
      if (model_.residual_norm(model_.state(), loads_, false) <= s_.derivatives_tolerance) break;
      if (it >= s_.derivatives_max_iterations)
        throw RunEnds{1, "Initial derivatives calculation 1 does not converge; aborting...", true};
      model_.derivatives_update(loads_, s_.dt);
      if (!peer_converged) {
        send_kinematics(2, model_.state());
        outstanding = true;
      }
    }
    if (!resumed_) {
      record(0.0);
      solved(0);
    }
    for (int k = first_step_; k <= s_.steps; ++k) {
      std::vector<BodyState> iterate = model_.predict(s_.dt);
      send_kinematics(2, iterate);  // send after predict
      outstanding = true;
      peer_converged = false;
      for (int j = 0;; ++j) {
        if (outstanding) {
          peer_converged = read_and_take(k, false) || peer_converged;
          outstanding = false;
        }
        if (peer_converged && model_.residual_norm(iterate, loads_) <= s_.tolerance) break;
        if (j >= s_.max_iterations)
          throw RunEnds{1, "Max iterations number " + std::to_string(s_.max_iterations) +
                               " has been reached during step " + std::to_string(k), true};
        iterate = model_.solve(s_.dt, loads_);
        if (!peer_converged) {
          send_kinematics(2, iterate);
          outstanding = true;
        }
      }
      model_.accept(iterate);
      record(k * s_.dt);
      solved(k);
    }
  }

  void write_out(const std::vector<BodyState>& bodies) {
    last_sent_ = bodies;
    const std::string err = write_out_file(s_.files, s_.shape, wire_nodes(bodies));
    if (!err.empty()) throw RunEnds{1, err, false};
    ++out_.kinematics_sent;
  }

  void read_in() {
    LoadsMessage m;
    const std::string err = read_in_file(s_.files, s_.shape, m);
    if (!err.empty()) throw RunEnds{1, err, false};
    out_.answers.push_back(6);
    for (std::size_t i = 0; i < m.force.size(); ++i) {
      loads_.force[i] = m.force[i];
      loads_.moment_z[i] = rotates() ? model_.node_moment_z(i, last_sent_[i], m.force[i], m.moment[i]) : 0.0;
    }
    out_.last_loads = m;
  }

  void run_files() {
    write_out(model_.state());
    read_in();  // the initial-derivatives solve
    if (model_.residual_norm(model_.state(), loads_, false) > s_.derivatives_tolerance)
      model_.derivatives_update(loads_, s_.dt);
    write_out(model_.state());  // after the derivatives (x0, v0 restored)
    record(0.0);
    for (int k = 1; k <= s_.steps; ++k) {
      read_in();  // at the step's first residual
      model_.accept(converge_with_frozen_loads(model_.predict(s_.dt)));
      record(k * s_.dt);
      write_out(model_.state());
    }
  }

  void run_none() {
    // One-way stream (spec §5.3): start-up, after the derivatives, after every step
    // (1002 messages for 1000 steps, verified). Nothing is read.
    send_kinematics(6, model_.state());
    if (model_.residual_norm(model_.state(), loads_, false) > s_.derivatives_tolerance)
      model_.derivatives_update(loads_, s_.dt);
    send_kinematics(6, model_.state());
    record(0.0);
    for (int k = 1; k <= s_.steps; ++k) {
      model_.accept(converge_with_frozen_loads(model_.predict(s_.dt)));
      record(k * s_.dt);
      send_kinematics(6, model_.state());
    }
  }

  PeerSetup s_;
  OscillatorModel model_;
  PeerSocket sock_;
  PeerOutcome out_;
  NodeState ref_;
  NodeLoads loads_;
  std::vector<BodyState> last_sent_;
  std::unique_ptr<std::ofstream> klog_;  // pose the next loads answer refers to
  std::unique_ptr<std::ofstream> llog_;  // --loads-log
  PeerState done_;          // after the last step solved with the peer's loads
  bool have_done_ = false;
  int first_step_ = 1;      // --resume: the step after the restored one
  bool resumed_ = false;
};

}  // namespace

std::vector<BodyState> default_initial_states(std::uint32_t nodes) {
  std::vector<BodyState> v(nodes);
  for (std::uint32_t i = 0; i < nodes; ++i) {
    v[i].x = {1.0 * i, -0.5 * i, 0.1 * (i + 1)};
    v[i].v = {0.02 * i, 0.05 * (i + 1), -0.01 * i};
    v[i].theta = 0.1 * (i + 1);
    v[i].theta_dot = 0.5;
  }
  return v;
}

NodeState reference_node_state(std::uint32_t label) {
  NodeState r;
  r.label = label;
  r.x = {0.5, -1.0, 2.0};
  r.R = multiply(rotation_about_y(0.4), rotation_about_x(-0.2));
  return r;
}

PeerOutcome run_mbdyn_test_peer(const PeerSetup& setup) { return PeerRun(setup).run(); }

}  // namespace dembridge::mbdyn::testpeer
