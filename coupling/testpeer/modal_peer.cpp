#include "modal_peer.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

namespace dembridge::mbdyn::testpeer {

namespace {

struct Ends {
  int status;
  std::string why;
};

class ModalRun {
 public:
  explicit ModalRun(const ModalPeerSetup& s) : s_(s), m_(s.mass.size()) {
    cur_.q = s.q0.empty() ? std::vector<double>(m_, 0.0) : s.q0;
    cur_.qdot = s.qdot0.empty() ? std::vector<double>(m_, 0.0) : s.qdot0;
    cur_.qddot.assign(m_, 0.0);
    cur_.p.assign(m_, 0.0);
  }

  ModalPeerOutcome run() {
    try {
      if (!s_.resume_state.empty()) resume();
      if (!s_.loads_log.empty()) {
        llog_ = std::make_unique<std::ofstream>(s_.loads_log);
        if (!*llog_) throw Ends{1, "cannot write the loads log " + s_.loads_log};
        llog_->precision(17);
      }
      connect_and_negotiate();
      if (s_.resume_state.empty()) {
        send_states(s_.tight ? 2 : 6, cur_);
        read_loads();  // initial derivatives: q''0 from the t0 answer, q0 and q'0 kept
        for (std::size_t i = 0; i < m_; ++i)
          cur_.qddot[i] = (cur_.p[i] - s_.damping[i] * cur_.qdot[i] - s_.stiffness[i] * cur_.q[i]) / s_.mass[i];
        solved(0);
      }
      for (int k = first_step_; k <= s_.steps; ++k) {
        if (s_.tight) {
          iterate(k);
        } else {
          send_states(6, cur_);
          read_loads();
          cur_ = solve(cur_.p, k * s_.dt);
        }
        solved(k);
      }
      const std::uint8_t five = 5;
      sock_.send_bytes(&five, 1);
      out_.exit_status = 0;
      out_.log = "End of simulation";
    } catch (const Ends& e) {
      out_.exit_status = e.status;
      out_.log = e.why;
    }
    sock_.close_now();
    if (!s_.save_state.empty() && have_done_) {
      const std::string err = save();
      if (!err.empty()) out_.log += "; " + err;
    }
    return out_;
  }

 private:
  void connect_and_negotiate() {
    int port = -1;
    std::string err = sock_.listen_on(s_.place, &port);
    if (err.empty() && s_.on_listening) s_.on_listening();
    if (err.empty()) err = sock_.accept_client(s_.accept_timeout_s);
    if (!err.empty()) throw Ends{1, err};
    sock_.set_io_timeout(s_.io_timeout_s);
    std::uint8_t req[9];
    if (sock_.receive_all(req, 9) != 9) throw Ends{1, "negotiation: short request"};
    std::uint32_t flags, n;
    std::memcpy(&flags, req + 1, 4);
    std::memcpy(&n, req + 5, 4);
    // MBDyn checks the modal flag, the rigid (reference-node) bit and the mode count.
    std::string why;
    if (req[0] != 7) why = "expected command 7";
    else if (!(flags & 0x1)) why = "modal flag missing";
    else if (flags & 0x4) why = "rigid part requested, element has type modal";
    else if (n != m_) why = "mode count mismatch (local=" + std::to_string(m_) + ", remote=" + std::to_string(n) + ")";
    const std::uint8_t answer = why.empty() ? 8 : 5;
    sock_.send_bytes(&answer, 1);
    if (!why.empty()) throw Ends{1, "ModalExt: negotiation failed: " + why};
  }

  void send_states(std::uint8_t cmd, const ModalSample& state) {
    std::vector<double> payload(state.q);
    payload.insert(payload.end(), state.qdot.begin(), state.qdot.end());
    if (!sock_.send_bytes(&cmd, 1) || !sock_.send_bytes(payload.data(), payload.size() * sizeof(double)))
      throw Ends{2, "send() to peer failed: peer gone"};
    ++out_.kinematics_sent;
  }

  // Reads one answer into cur_.p; returns its command (6, or 2 in tight coupling).
  std::uint8_t read_loads() {
    std::uint8_t cmd = 0;
    if (sock_.receive_all(&cmd, 1) != 1) throw Ends{2, "no answer from the peer"};
    if (cmd == 5) throw Ends{2, "peer requested end of simulation; MBDyn was interrupted"};
    if (cmd != 6 && !(s_.tight && cmd == 2))
      throw Ends{1, "received command " + std::to_string(cmd) + (s_.tight ? " in tight coupling" : " in loose coupling")};
    if (sock_.receive_all(cur_.p.data(), m_ * sizeof(double)) != m_ * sizeof(double))
      throw Ends{1, "short load message"};
    if (llog_) {
      *llog_ << answers_++ << ' ' << int(cmd);
      for (double v : cur_.p) *llog_ << ' ' << v;
      *llog_ << '\n';
    }
    return cmd;
  }

  // Tight: every iterate is the step solved with the last loads answered, until the answer is 6;
  // the step is then solved with the loads of that answer.
  void iterate(int k) {
    const double t = k * s_.dt;
    const ModalSample start = cur_;
    for (int j = 0;; ++j) {
      if (j >= s_.max_iterations)
        throw Ends{1, "Max iterations number " + std::to_string(s_.max_iterations) + " has been reached during step " +
                          std::to_string(k)};
      const ModalSample iterate = solve_from(start, cur_.p, t);
      send_states(2, iterate);
      if (read_loads() == 6) break;
    }
    cur_ = solve_from(start, cur_.p, t);
  }

  ModalSample solve(const std::vector<double>& p, double t) const { return solve_from(cur_, p, t); }

  // Crank nicolson from state `from` for given p: solve (M + T/2 C + T^2/4 K) q'' = p - C q'* - K q*.
  ModalSample solve_from(const ModalSample& from, const std::vector<double>& p, double t) const {
    const double T = s_.dt;
    ModalSample next = from;
    next.t = t;
    next.p = p;
    for (std::size_t i = 0; i < m_; ++i) {
      const double qd_star = from.qdot[i] + 0.5 * T * from.qddot[i];
      const double q_star = from.q[i] + T * from.qdot[i] + 0.25 * T * T * from.qddot[i];
      const double lhs = s_.mass[i] + 0.5 * T * s_.damping[i] + 0.25 * T * T * s_.stiffness[i];
      next.qddot[i] = (p[i] - s_.damping[i] * qd_star - s_.stiffness[i] * q_star) / lhs;
      next.qdot[i] = from.qdot[i] + 0.5 * T * (from.qddot[i] + next.qddot[i]);
      next.q[i] = from.q[i] + 0.5 * T * (from.qdot[i] + next.qdot[i]);
    }
    return next;
  }

  // The state after step k, solved with the peer's loads (what --save-state keeps).
  void solved(int k) {
    out_.trajectory.push_back(cur_);
    done_step_ = k;
    have_done_ = true;
  }

  // State file: a title line, the step, the mode count, then t, q, q', q'', p at 17 digits.
  std::string save() const {
    std::ofstream f(s_.save_state);
    f.precision(17);
    f << "mbdyn_testpeer modal state\n" << done_step_ << ' ' << m_ << '\n' << cur_.t << '\n';
    for (const auto* v : {&cur_.q, &cur_.qdot, &cur_.qddot, &cur_.p}) {
      for (double x : *v) f << x << ' ';
      f << '\n';
    }
    return f ? "" : "cannot write the state file " + s_.save_state;
  }

  void resume() {
    std::ifstream f(s_.resume_state);
    std::string title;
    std::size_t modes = 0;
    int step = -1;
    std::getline(f, title);
    f >> step >> modes >> cur_.t;
    if (!f || title != "mbdyn_testpeer modal state" || step < 0)
      throw Ends{1, "--resume " + s_.resume_state + ": not a modal state file of mbdyn_testpeer"};
    if (modes != m_)
      throw Ends{1, "--resume " + s_.resume_state + ": the state has " + std::to_string(modes) + " modes, the body " +
                        std::to_string(m_)};
    for (auto* v : {&cur_.q, &cur_.qdot, &cur_.qddot, &cur_.p})
      for (double& x : *v) f >> x;
    if (!f) throw Ends{1, "--resume " + s_.resume_state + ": truncated"};
    first_step_ = step + 1;
    solved(step);
  }

  ModalPeerSetup s_;
  std::size_t m_;
  int first_step_ = 1, done_step_ = 0;
  bool have_done_ = false;
  long answers_ = 0;
  std::unique_ptr<std::ofstream> llog_;  // --loads-log
  PeerSocket sock_;
  ModalSample cur_;
  ModalPeerOutcome out_;
};

}  // namespace

ModalPeerOutcome run_modal_test_peer(const ModalPeerSetup& setup) { return ModalRun(setup).run(); }

}  // namespace dembridge::mbdyn::testpeer
