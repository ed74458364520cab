#include "peer_state_file.h"

#include <fstream>
#include <sstream>

namespace dembridge::mbdyn::testpeer {

namespace {

void put(std::ostream& o, const BodyState& b) {
  for (const V3* v : {&b.x, &b.v, &b.a, &b.q, &b.qp})
    for (double c : *v) o << ' ' << c;
  for (double c : {b.theta, b.theta_dot, b.theta_ddot, b.q_theta, b.qp_theta}) o << ' ' << c;
  o << '\n';
}

bool get(std::istream& in, BodyState& b) {
  for (V3* v : {&b.x, &b.v, &b.a, &b.q, &b.qp})
    for (double& c : *v) in >> c;
  for (double* c : {&b.theta, &b.theta_dot, &b.theta_ddot, &b.q_theta, &b.qp_theta}) in >> *c;
  return static_cast<bool>(in);
}

}  // namespace

std::string write_peer_state(const std::string& path, const PeerState& s) {
  std::ofstream f(path);
  if (!f) return "cannot write the state file " + path;
  f.precision(17);
  f << "# mbdyn_testpeer state: step, nodes, states kept; then per node x v a q qp (3 each) theta theta' "
       "theta'' q_theta qp_theta, at the step and one step before\n";
  f << s.step << ' ' << s.state.size() << ' ' << (s.older.empty() ? 1 : 2) << '\n';
  for (const BodyState& b : s.state) put(f, b);
  for (const BodyState& b : s.older) put(f, b);
  return f ? "" : "cannot write the state file " + path;
}

std::string read_peer_state(const std::string& path, std::size_t nodes, PeerState& s) {
  std::ifstream f(path);
  if (!f) return "cannot read the state file " + path;
  std::string line;
  std::getline(f, line);
  std::size_t n = 0;
  int kept = 0;
  if (!(f >> s.step >> n >> kept) || s.step < 0 || (kept != 1 && kept != 2))
    return "the state file " + path + " is not an mbdyn_testpeer state";
  if (n != nodes)
    return "the state file " + path + " has " + std::to_string(n) + " nodes, --nodes " + std::to_string(nodes);
  s.state.assign(n, BodyState{});
  s.older.assign(kept == 2 ? n : 0, BodyState{});
  for (BodyState& b : s.state)
    if (!get(f, b)) return "the state file " + path + " is truncated";
  for (BodyState& b : s.older)
    if (!get(f, b)) return "the state file " + path + " is truncated";
  return "";
}

}  // namespace dembridge::mbdyn::testpeer
