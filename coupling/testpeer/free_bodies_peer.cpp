#include "free_bodies_peer.h"

#include <algorithm>
#include <cstring>
#include <exception>
#include <fstream>
#include <memory>

namespace dembridge::mbdyn::testpeer {

namespace {

struct Ends {
  int status;
  std::string why;
};

V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

class FreeBodiesRun {
 public:
  explicit FreeBodiesRun(const FreeBodiesPeerSetup& s) : s_(s), model_(bodies_of(s), s.gravity, s.derivatives_coefficient, s.tolerance) {
    shape_.nodes = static_cast<std::uint32_t>(s.points.size());
    shape_.orientation = Orientation::Matrix;
    shape_.labels = true;
    shape_.reference_node = true;
    if (!s.trajectory.empty()) {
      traj_ = std::make_unique<std::ofstream>(s.trajectory);
      traj_->precision(17);
    }
  }

  FreeBodiesPeerOutcome run() {
    try {
      connect_and_negotiate();
      if (s_.tight) run_tight();
      else run_loose();
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
  void run_loose() {
    send_kinematics(6, model_.state());
    model_.derivatives(law(read_loads(false)), s_.dt);
    record(0.0);
    for (int k = 1; k <= s_.steps; ++k) {
      send_kinematics(6, model_.predict(s_.dt));
      const LoadsMessage m = read_loads(false);
      try {
        model_.step(law(m), s_.dt);
      } catch (const std::exception& e) {
        throw Ends{1, e.what()};
      }
      record(k * s_.dt);
    }
  }

  // MBDyn's tight coupling: its initial derivatives iterate (gravity: a non-zero residual), so
  // t0's state goes out once; then per step the prediction and, after every Newton update, the
  // iterate, until the peer answers 6; MBDyn then iterates on with those loads, silently.
  void run_tight() {
    send_kinematics(2, model_.state());
    LoadsMessage m = read_loads(true);
    while (last_cmd_ == 2) {  // the peer asks for another start-up iterate: the state is kept
      model_.derivatives(law(m), s_.dt);
      send_kinematics(2, model_.state());
      m = read_loads(true);
    }
    model_.derivatives(law(m), s_.dt);
    record(0.0);
    for (int k = 1; k <= s_.steps; ++k) {
      model_.begin_step(s_.dt);
      send_kinematics(2, model_.iterate());
      BodyLoadsLaw loads = law(read_loads(true));
      bool peer_converged = last_cmd_ == 6;
      for (int j = 0;; ++j) {
        if (j > 0 && peer_converged && model_.residual(loads) <= model_.tolerance()) break;
        if (j >= s_.max_iterations)
          throw Ends{1, "Max iterations number " + std::to_string(s_.max_iterations) + " has been reached during step " +
                            std::to_string(k)};
        model_.update(loads);
        if (!peer_converged) {
          send_kinematics(2, model_.iterate());
          loads = law(read_loads(true));
          peer_converged = last_cmd_ == 6;
        }
      }
      model_.accept();
      record(k * s_.dt);
    }
  }

  static std::vector<FreeBody> bodies_of(const FreeBodiesPeerSetup& s) {
    std::vector<FreeBody> b{s.reference};
    b.insert(b.end(), s.points.begin(), s.points.end());
    return b;
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
    const std::uint32_t want = negotiation_flags(shape_);
    std::string why;
    if (req[0] != 7) why = "expected command 7";
    else if ((flags & 0xF1F) != (want & 0xF1F)) why = "flags mismatch (local=" + std::to_string(want) + ", remote=" + std::to_string(flags) + ")";
    else if (n != shape_.nodes) why = "node count mismatch";
    const std::uint8_t answer = why.empty() ? 8 : 5;
    sock_.send_bytes(&answer, 1);
    if (!why.empty()) throw Ends{1, "StructExtForce: negotiation response failed: " + why};
  }

  // The reference node absolute, the points relative to it in its frame (MBDyn's layout).
  void send_kinematics(std::uint8_t cmd, const std::vector<FreeBody>& b) {
    const FreeBody& r = b[0];
    NodeState ref;
    ref.label = s_.reference_label;
    ref.x = r.x;
    ref.R = r.R;
    ref.v = r.v;
    ref.w = r.w;
    const Mat3 RrT = transpose(r.R);
    std::vector<NodeState> nodes;
    for (std::size_t i = 1; i < b.size(); ++i) {
      NodeState n;
      n.label = s_.labels[i - 1];
      V3 dx, dv, dw;
      const V3 wxd = cross(r.w, V3{b[i].x[0] - r.x[0], b[i].x[1] - r.x[1], b[i].x[2] - r.x[2]});
      for (int k = 0; k < 3; ++k) {
        dx[k] = b[i].x[k] - r.x[k];
        dv[k] = b[i].v[k] - r.v[k] - wxd[k];
        dw[k] = b[i].w[k] - r.w[k];
      }
      n.x = rotate_vector(RrT, dx);
      n.R = multiply(RrT, b[i].R);
      n.v = rotate_vector(RrT, dv);
      n.w = rotate_vector(RrT, dw);
      nodes.push_back(n);
    }
    const std::vector<std::uint8_t> payload = encode_kinematics_payload(shape_, ref, nodes);
    if (!sock_.send_bytes(&cmd, 1) || !sock_.send_bytes(payload.data(), payload.size()))
      throw Ends{2, "send() to peer failed: peer gone"};
    ++out_.kinematics_sent;
  }

  LoadsMessage read_loads(bool tight) {
    std::uint8_t cmd = 0;
    if (sock_.receive_all(&cmd, 1) != 1) throw Ends{2, "no answer from the peer"};
    if (cmd == 5) throw Ends{2, "peer requested end of simulation; MBDyn was interrupted"};
    if (cmd != 6 && !(tight && cmd == 2))
      throw Ends{1, "received command " + std::to_string(cmd) + (tight ? "" : " in loose coupling")};
    last_cmd_ = cmd;
    const std::size_t want = loads_payload_size(shape_);
    std::vector<std::uint8_t> buf(want);
    if (sock_.receive_all(buf.data(), want) != want) throw Ends{1, "StructExtForce: short load message"};
    LoadsMessage m = decode_loads_payload(shape_, buf.data(), want);
    if (m.ref_label != s_.reference_label) throw Ends{1, "invalid reference node label " + std::to_string(m.ref_label)};
    // `sorted, no`: the slot for point k is the position of slot k's label in the element's list
    slot_.assign(m.labels.size(), 0);
    for (std::size_t k = 0; k < m.labels.size(); ++k) {
      const auto it = std::find(s_.labels.begin(), s_.labels.end(), m.labels[k]);
      if (it == s_.labels.end()) throw Ends{1, "invalid " + std::to_string(k) + "-th label " + std::to_string(m.labels[k])};
      slot_[k] = static_cast<std::size_t>(it - s_.labels.begin());
    }
    return m;
  }

  // The answer as loads on the bodies at their current states (the reference node's rotation
  // and position as they are in each residual).
  BodyLoadsLaw law(const LoadsMessage& m) const {
    const std::vector<std::size_t> slot = slot_;
    return [m, slot](const std::vector<FreeBody>& b, std::vector<V3>& force, std::vector<V3>& moment) {
      const FreeBody& r = b[0];
      V3 F0 = rotate_vector(r.R, m.ref_force), M0 = rotate_vector(r.R, m.ref_moment);
      for (std::size_t k = 1; k < b.size(); ++k) {
        const V3 f = rotate_vector(r.R, m.force[slot[k - 1]]), mo = rotate_vector(r.R, m.moment[slot[k - 1]]);
        const V3 arm{b[k].x[0] - r.x[0], b[k].x[1] - r.x[1], b[k].x[2] - r.x[2]};
        const V3 t = cross(arm, f);
        for (int a = 0; a < 3; ++a) {
          force[k][a] += f[a];
          moment[k][a] += mo[a];
          F0[a] -= f[a];
          M0[a] -= mo[a] + t[a];
        }
      }
      for (int a = 0; a < 3; ++a) {
        force[0][a] += F0[a];
        moment[0][a] += M0[a];
      }
    };
  }

  void record(double t) {
    if (!traj_) return;
    *traj_ << t;
    for (const FreeBody& b : model_.state()) {
      for (double v : b.x) *traj_ << ' ' << v;
      for (const auto& row : b.R)
        for (double v : row) *traj_ << ' ' << v;
      for (double v : b.v) *traj_ << ' ' << v;
      for (double v : b.w) *traj_ << ' ' << v;
    }
    *traj_ << '\n';
  }

  FreeBodiesPeerSetup s_;
  FreeBodiesModel model_;
  ElementShape shape_;
  PeerSocket sock_;
  std::vector<std::size_t> slot_;
  std::uint8_t last_cmd_ = 0;
  std::unique_ptr<std::ofstream> traj_;
  FreeBodiesPeerOutcome out_;
};

}  // namespace

FreeBodiesPeerOutcome run_free_bodies_test_peer(const FreeBodiesPeerSetup& setup) { return FreeBodiesRun(setup).run(); }

}  // namespace dembridge::mbdyn::testpeer
