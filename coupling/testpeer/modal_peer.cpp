#include "modal_peer.h"

#include <cstdint>
#include <cstring>

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
      connect_and_negotiate();
      send_states();
      read_loads();  // initial derivatives: q''0 from the t0 answer, q0 and q'0 kept
      for (std::size_t i = 0; i < m_; ++i)
        cur_.qddot[i] = (cur_.p[i] - s_.damping[i] * cur_.qdot[i] - s_.stiffness[i] * cur_.q[i]) / s_.mass[i];
      out_.trajectory.push_back(cur_);
      for (int k = 1; k <= s_.steps; ++k) {
        send_states();
        read_loads();
        step(k * s_.dt);
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

  void send_states() {
    std::vector<double> payload(cur_.q);
    payload.insert(payload.end(), cur_.qdot.begin(), cur_.qdot.end());
    const std::uint8_t six = 6;
    if (!sock_.send_bytes(&six, 1) || !sock_.send_bytes(payload.data(), payload.size() * sizeof(double)))
      throw Ends{2, "send() to peer failed: peer gone"};
    ++out_.kinematics_sent;
  }

  void read_loads() {
    std::uint8_t cmd = 0;
    if (sock_.receive_all(&cmd, 1) != 1) throw Ends{2, "no answer from the peer"};
    if (cmd == 5) throw Ends{2, "peer requested end of simulation; MBDyn was interrupted"};
    if (cmd != 6) throw Ends{1, "received command " + std::to_string(cmd) + " in loose coupling"};
    if (sock_.receive_all(cur_.p.data(), m_ * sizeof(double)) != m_ * sizeof(double))
      throw Ends{1, "short load message"};
  }

  // Crank nicolson for given p: solve (M + T/2 C + T^2/4 K) q'' = p - C q'* - K q*.
  void step(double t) {
    const double T = s_.dt;
    ModalSample next = cur_;
    next.t = t;
    for (std::size_t i = 0; i < m_; ++i) {
      const double qd_star = cur_.qdot[i] + 0.5 * T * cur_.qddot[i];
      const double q_star = cur_.q[i] + T * cur_.qdot[i] + 0.25 * T * T * cur_.qddot[i];
      const double lhs = s_.mass[i] + 0.5 * T * s_.damping[i] + 0.25 * T * T * s_.stiffness[i];
      next.qddot[i] = (cur_.p[i] - s_.damping[i] * qd_star - s_.stiffness[i] * q_star) / lhs;
      next.qdot[i] = cur_.qdot[i] + 0.5 * T * (cur_.qddot[i] + next.qddot[i]);
      next.q[i] = cur_.q[i] + 0.5 * T * (cur_.qdot[i] + next.qdot[i]);
    }
    cur_ = next;
    out_.trajectory.push_back(cur_);
  }

  ModalPeerSetup s_;
  std::size_t m_;
  PeerSocket sock_;
  ModalSample cur_;
  ModalPeerOutcome out_;
};

}  // namespace

ModalPeerOutcome run_modal_test_peer(const ModalPeerSetup& setup) { return ModalRun(setup).run(); }

}  // namespace dembridge::mbdyn::testpeer
