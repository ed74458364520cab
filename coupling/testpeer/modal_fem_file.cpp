#include "modal_fem_file.h"

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace dembridge::mbdyn::testpeer {

namespace {

class Tokens {
 public:
  Tokens(std::string file, int record, std::vector<std::string> t) : file_(std::move(file)), record_(record), t_(std::move(t)) {}
  std::string word() {
    if (i_ >= t_.size()) fail("ends early");
    return t_[i_++];
  }
  double number() {
    const std::string w = word();
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (w.empty() || *end != '\0') fail("has '" + w + "' where a number was expected");
    return v;
  }
  std::size_t count() {
    const double v = number();
    if (v < 0 || v != static_cast<double>(static_cast<std::size_t>(v))) fail("has a non-integer count");
    return static_cast<std::size_t>(v);
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error(file_ + ": RECORD GROUP " + std::to_string(record_) + " " + why);
  }

 private:
  std::string file_;
  int record_;
  std::vector<std::string> t_;
  std::size_t i_ = 0;
};

}  // namespace

ModalFemData read_modal_fem_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open the modal FEM file " + path);
  std::map<int, std::vector<std::string>> records;
  int current = 0;
  const std::string header = "** RECORD GROUP ";
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("** END OF FILE", 0) == 0) break;
    if (line.rfind(header, 0) == 0) {
      current = std::atoi(line.c_str() + header.size());
      if (current <= 0 || records.count(current)) throw std::runtime_error(path + ": bad or repeated '" + line + "'");
      records[current];
      continue;
    }
    if (line.rfind("**", 0) == 0) continue;
    std::istringstream words(line);
    for (std::string w; words >> w;) {
      if (current == 0) throw std::runtime_error(path + ": data before RECORD GROUP 1");
      records[current].push_back(w);
    }
  }
  for (int r : {1, 2, 5, 6, 7, 8, 9, 10, 11})
    if (!records.count(r)) throw std::runtime_error(path + ": RECORD GROUP " + std::to_string(r) + " missing");
  for (const auto& [r, t] : records)
    if (r == 12 || r > 13)
      throw std::runtime_error(path + ": RECORD GROUP " + std::to_string(r) +
                               " (given inertia or invariants) is not supported by the test peer");
  auto tokens = [&](int r) { return Tokens(path, r, records[r]); };

  ModalFemData d;
  Tokens h = tokens(1);
  h.word();  // revision
  const std::size_t nodes = h.count();
  const std::size_t normal = h.count(), attachment = h.count(), constraint = h.count(), rejected = h.count();
  if (normal + attachment + constraint < rejected + 1) h.fail("declares no modes");
  const std::size_t modes = normal + attachment + constraint - rejected;
  if (nodes == 0) h.fail("declares no FEM nodes");

  Tokens lab = tokens(2);
  for (std::size_t n = 0; n < nodes; ++n) d.labels.push_back(lab.word());
  d.q0.assign(modes, 0.0);
  d.qdot0.assign(modes, 0.0);
  if (records.count(3)) {
    Tokens t = tokens(3);
    for (double& q : d.q0) q = t.number();
  }
  if (records.count(4)) {
    Tokens t = tokens(4);
    for (double& q : d.qdot0) q = t.number();
  }
  d.position.assign(nodes, V3{});
  for (int c = 0; c < 3; ++c) {
    Tokens t = tokens(5 + c);
    for (std::size_t n = 0; n < nodes; ++n) d.position[n][c] = t.number();
  }
  Tokens sh = tokens(8);
  d.shape_t.assign(modes, std::vector<V3>(nodes));
  d.shape_r.assign(modes, std::vector<V3>(nodes));
  for (std::size_t m = 0; m < modes; ++m)
    for (std::size_t n = 0; n < nodes; ++n) {
      for (int c = 0; c < 3; ++c) d.shape_t[m][n][c] = sh.number();
      for (int c = 0; c < 3; ++c) d.shape_r[m][n][c] = sh.number();
    }
  auto matrix = [&](int r, std::vector<double>& out) {
    out.assign(modes * modes, 0.0);
    if (!records.count(r)) return;
    Tokens t = tokens(r);
    for (double& v : out) v = t.number();
  };
  matrix(9, d.mass);
  matrix(10, d.stiffness);
  matrix(13, d.damping);  // MBDyn's default `damping from file`; zero without record 13
  Tokens lm = tokens(11);
  for (std::size_t n = 0; n < nodes; ++n) {
    d.node_mass.push_back(lm.number());
    lm.number();
    lm.number();
    V3 J;
    for (double& j : J) j = lm.number();
    d.node_inertia.push_back(J);
  }
  return d;
}

}  // namespace dembridge::mbdyn::testpeer
