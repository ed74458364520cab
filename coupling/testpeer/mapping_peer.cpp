#include "mapping_peer.h"

#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace dembridge::mbdyn::testpeer {

std::vector<SparseEntry> read_sparse_mapping(const std::string& path, int rows, int cols) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open mapping file " + path);
  std::map<std::pair<int, int>, double> m;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream s(line);
    int r = 0, c = 0;
    double v = 0;
    std::string rest;
    if (!(s >> r >> c >> v) || (s >> rest) || r < 1 || r > rows || c < 1 || c > cols)
      throw std::runtime_error(path + ":" + std::to_string(lineno) + ": expected `row col value` with row 1.." +
                               std::to_string(rows) + ", col 1.." + std::to_string(cols));
    m[{r - 1, c - 1}] = v;
  }
  std::vector<SparseEntry> out;
  for (const auto& [rc, v] : m) out.push_back({rc.first, rc.second, v});
  return out;
}

namespace {

struct Ends {
  int status;
  std::string why;
};

V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

class MappingRun {
 public:
  explicit MappingRun(const MappingPeerSetup& s) : s_(s), model_(s.model) {
    if (!s.trajectory.empty()) {
      traj_ = std::make_unique<std::ofstream>(s.trajectory);
      traj_->precision(17);
    }
  }

  MappingPeerOutcome run() {
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
    } catch (const std::exception& e) {
      out_.exit_status = 1;
      out_.log = e.what();
    }
    sock_.close_now();
    return out_;
  }

 private:
  void run_loose() {
    send_kinematics(6);
    model_.derivatives(read_loads(false), s_.dt, 1, s_.derivatives_max_iterations);
    record(0.0);
    for (int k = 1; k <= s_.steps; ++k) {
      model_.begin_step(s_.dt);
      send_kinematics(6);
      solve_step(read_loads(false), true, k);
      record(k * s_.dt);
    }
  }

  // The start-up exchange once (answered 6 by the recording peer; another answer 2 gets the same
  // state again), then MBDyn's tight steps.
  void run_tight() {
    send_kinematics(2);
    NodalLoads loads = read_loads(true);
    while (last_cmd_ == 2) {
      send_kinematics(2);
      loads = read_loads(true);
    }
    model_.derivatives(loads, s_.dt, 2, s_.derivatives_max_iterations);
    record(0.0);
    for (int k = 1; k <= s_.steps; ++k) {
      model_.begin_step(s_.dt);
      send_kinematics(2);
      NodalLoads first = read_loads(true);  // before reading last_cmd_ (argument order is unspecified)
      solve_step(first, last_cmd_ == 6, k);
      record(k * s_.dt);
    }
  }

  void solve_step(NodalLoads loads, bool peer_converged, int step) {
    for (int j = 0;; ++j) {
      if (peer_converged && model_.residual_norm(loads) <= s_.tolerance) break;
      if (j >= s_.max_iterations)
        throw Ends{1, "Max iterations number " + std::to_string(s_.max_iterations) +
                          " has been reached during step " + std::to_string(step)};
      model_.update(loads);
      if (!peer_converged) {
        send_kinematics(2);
        loads = read_loads(true);
        peer_converged = last_cmd_ == 6;
      }
    }
    model_.accept();
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
    std::string why;
    if (req[0] != 7) why = "expected command 7";
    else if ((flags & 0xF1F) != 0x2) why = "flags mismatch (local=2, remote=" + std::to_string(flags) + ")";
    else if (n != static_cast<std::uint32_t>(s_.mapped_points)) why = "mapped points count mismatch";
    const std::uint8_t answer = why.empty() ? 8 : 5;
    sock_.send_bytes(&answer, 1);
    if (!why.empty()) throw Ends{1, "StructMappingExtForce: negotiation response failed: " + why};
  }

  void send_kinematics(std::uint8_t cmd) {
    const std::vector<CantileverNode> nodes = model_.nodes();
    const std::size_t P = nodes.size() * s_.offsets.size(), M = static_cast<std::size_t>(s_.mapped_points);
    std::vector<double> x(3 * P), xp(3 * P);
    std::size_t p3 = 0;
    for (const CantileverNode& n : nodes)
      for (const V3& o : s_.offsets) {
        const V3 f = rotate_vector(n.R, o);
        const V3 wf = cross(n.w, f);
        for (int a = 0; a < 3; ++a) {
          x[p3 + a] = n.x[a] + f[a];
          xp[p3 + a] = n.v[a] + wf[a];
        }
        p3 += 3;
      }
    std::vector<double> q(6 * M, 0.0);
    for (const SparseEntry& e : s_.mapping) {
      q[e.row] += e.value * x[e.col];
      q[3 * M + e.row] += e.value * xp[e.col];
    }
    if (!sock_.send_bytes(&cmd, 1) || !sock_.send_bytes(q.data(), q.size() * sizeof(double)))
      throw Ends{2, "send() to peer failed: peer gone"};
    ++out_.kinematics_sent;
  }

  // The loads as node forces and moments at the nodes' current orientations.
  NodalLoads read_loads(bool tight) {
    std::uint8_t cmd = 0;
    if (sock_.receive_all(&cmd, 1) != 1) throw Ends{2, "no answer from the peer"};
    if (cmd == 5) throw Ends{2, "peer requested end of simulation; MBDyn was interrupted"};
    if (cmd != 6 && !(tight && cmd == 2))
      throw Ends{1, "received command " + std::to_string(cmd) + (tight ? "" : " in loose coupling")};
    last_cmd_ = cmd;
    const std::size_t M = static_cast<std::size_t>(s_.mapped_points);
    std::vector<double> p(3 * M);
    if (sock_.receive_all(p.data(), p.size() * sizeof(double)) != p.size() * sizeof(double))
      throw Ends{1, "StructMappingExtForce: recv() failed (short load message)"};
    const std::vector<CantileverNode> nodes = model_.nodes();
    std::vector<double> f(3 * nodes.size() * s_.offsets.size(), 0.0);
    for (const SparseEntry& e : s_.mapping) f[e.col] += e.value * p[e.row];
    NodalLoads loads;
    loads.force.assign(nodes.size(), V3{0, 0, 0});
    loads.moment.assign(nodes.size(), V3{0, 0, 0});
    std::size_t p3 = 0;
    for (std::size_t k = 0; k < nodes.size(); ++k)
      for (const V3& o : s_.offsets) {
        const V3 fo{f[p3], f[p3 + 1], f[p3 + 2]};
        const V3 arm = rotate_vector(nodes[k].R, o);
        const V3 t = cross(arm, fo);
        for (int a = 0; a < 3; ++a) {
          loads.force[k][a] += fo[a];
          loads.moment[k][a] += t[a];
        }
        p3 += 3;
      }
    return loads;
  }

  void record(double t) {
    if (!traj_) return;
    *traj_ << t;
    for (const CantileverNode& n : model_.nodes()) {
      for (double v : n.x) *traj_ << ' ' << v;
      for (const auto& row : n.R)
        for (double v : row) *traj_ << ' ' << v;
      for (double v : n.v) *traj_ << ' ' << v;
      for (double v : n.w) *traj_ << ' ' << v;
    }
    *traj_ << '\n';
  }

  MappingPeerSetup s_;
  CantileverModel model_;
  PeerSocket sock_;
  std::uint8_t last_cmd_ = 0;
  std::unique_ptr<std::ofstream> traj_;
  MappingPeerOutcome out_;
};

}  // namespace

MappingPeerOutcome run_mapping_test_peer(const MappingPeerSetup& setup) { return MappingRun(setup).run(); }

}  // namespace dembridge::mbdyn::testpeer
