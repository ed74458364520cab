#include "free_modal_body_peer.h"

#include <cstring>
#include <exception>
#include <fstream>
#include <memory>

#include "free_modal_body_model.h"

namespace dembridge::mbdyn::testpeer {

namespace {

struct Ends {
  int status;
  std::string why;
};

class FreeModalBodyRun {
 public:
  explicit FreeModalBodyRun(const FreeModalBodyPeerSetup& s)
      : s_(s),
        model_(s.fem, s.origin, s.x0, s.v0, s.w0, s.q0.empty() ? s.fem.q0 : s.q0,
               s.qdot0.empty() ? s.fem.qdot0 : s.qdot0, s.tolerance) {
    if (!s.trajectory.empty()) {
      traj_ = std::make_unique<std::ofstream>(s.trajectory);
      traj_->precision(17);
      *traj_ << "# t, x(3), R(9, row by row), v(3), w(3), q, q', q'' per mode\n";
    }
  }

  FreeModalBodyPeerOutcome run() {
    try {
      connect_and_negotiate();
      if (!s_.tight) {  // the t0 exchange: read by the (skipped) initial derivatives
        send_kinematics(6);
        read_loads();
      }
      record(0.0);
      for (int k = 1; k <= s_.steps; ++k) {
        step(k);
        record(k * s_.dt);
      }
      const std::uint8_t five = 5;
      sock_.send_bytes(&five, 1);
      out_.exit_status = 0;
      out_.log = "End of simulation";
    } catch (const Ends& e) {
      out_.exit_status = e.status;
      out_.log = e.why;
    } catch (const std::exception& e) {
      out_.exit_status = 1;
      out_.log = e.what();
    }
    sock_.close_now();
    return out_;
  }

 private:
  // One MBDyn step: the prediction goes out; the loose answer holds for the whole step, the
  // tight peer is sent every iterate until it answers 6; MBDyn's Newton ends at the first
  // residual within tolerance (after at least one update) once the peer has converged.
  void step(int k) {
    model_.predict(s_.dt);
    const std::uint8_t cmd = s_.tight ? 2 : 6;
    send_kinematics(cmd);
    ModalLoads loads = read_loads();
    bool peer_converged = !s_.tight || last_cmd_ == 6;
    for (int j = 0;; ++j) {
      const double r = model_.assemble(loads);
      if (j > 0 && peer_converged && r <= model_.tolerance()) break;
      if (j >= s_.max_iterations)
        throw Ends{1, "Max iterations number " + std::to_string(s_.max_iterations) +
                          " has been reached during step " + std::to_string(k)};
      model_.update();
      if (!peer_converged) {
        send_kinematics(cmd);
        loads = read_loads();
        peer_converged = last_cmd_ == 6;
      }
    }
  }

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
    // MBDyn checks the modal/nodal type, the rigid (reference-node) bit and the mode count
    std::string why;
    if (req[0] != 7) why = "expected command 7";
    else if ((flags & 0x3) != 0x1) why = "expecting MBC_MODAL (=1), got " + std::to_string(flags & 0x3);
    else if (!(flags & 0x4)) why = "reference node configuration mismatch (local=yes, remote=no)";
    else if (n != model_.modes())
      why = "mode number mismatch (local=" + std::to_string(model_.modes()) + ", remote=" + std::to_string(n) + ")";
    const std::uint8_t answer = why.empty() ? 8 : 5;
    sock_.send_bytes(&answer, 1);
    if (!why.empty()) throw Ends{1, "ExtModalForce: negotiation response failed: " + why};
  }

  void send_kinematics(std::uint8_t cmd) {
    const ModalBodyKinematics k = model_.kinematics();
    std::vector<double> p(k.x.begin(), k.x.end());
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) p.push_back(k.R[r][c]);  // column-major
    p.insert(p.end(), k.v.begin(), k.v.end());
    p.insert(p.end(), k.w.begin(), k.w.end());
    p.insert(p.end(), k.q.begin(), k.q.end());
    p.insert(p.end(), k.qdot.begin(), k.qdot.end());
    if (!sock_.send_bytes(&cmd, 1) || !sock_.send_bytes(p.data(), p.size() * sizeof(double)))
      throw Ends{2, "send() to peer failed: peer gone"};
    ++out_.kinematics_sent;
  }

  ModalLoads read_loads() {
    std::uint8_t cmd = 0;
    if (sock_.receive_all(&cmd, 1) != 1) throw Ends{2, "no answer from the peer"};
    if (cmd == 5) throw Ends{2, "peer requested end of simulation; MBDyn was interrupted"};
    if (cmd != 6 && !(s_.tight && cmd == 2))
      throw Ends{1, "received command " + std::to_string(cmd) + (s_.tight ? "" : " in loose coupling")};
    last_cmd_ = cmd;
    std::vector<double> v(6 + model_.modes());
    const std::size_t bytes = v.size() * sizeof(double);
    if (sock_.receive_all(v.data(), bytes) != bytes) throw Ends{1, "ExtModalForce: short load message"};
    ModalLoads L;
    for (int a = 0; a < 3; ++a) {
      L.force[a] = v[a];
      L.moment[a] = v[3 + a];
    }
    L.p.assign(v.begin() + 6, v.end());
    return L;
  }

  void record(double t) {
    if (!traj_) return;
    const ModalBodyKinematics k = model_.kinematics();
    *traj_ << t;
    for (double x : k.x) *traj_ << ' ' << x;
    for (const auto& row : k.R)
      for (double x : row) *traj_ << ' ' << x;
    for (double x : k.v) *traj_ << ' ' << x;
    for (double x : k.w) *traj_ << ' ' << x;
    const std::vector<double> qdd = model_.qddot();
    for (std::size_t j = 0; j < model_.modes(); ++j) *traj_ << ' ' << k.q[j] << ' ' << k.qdot[j] << ' ' << qdd[j];
    *traj_ << '\n';
  }

  FreeModalBodyPeerSetup s_;
  FreeModalBodyModel model_;
  PeerSocket sock_;
  std::uint8_t last_cmd_ = 0;
  std::unique_ptr<std::ofstream> traj_;
  FreeModalBodyPeerOutcome out_;
};

}  // namespace

FreeModalBodyPeerOutcome run_free_modal_body_test_peer(const FreeModalBodyPeerSetup& setup) {
  try {
    return FreeModalBodyRun(setup).run();
  } catch (const std::exception& e) {  // the model refused the setup
    FreeModalBodyPeerOutcome out;
    out.log = e.what();
    return out;
  }
}

}  // namespace dembridge::mbdyn::testpeer
