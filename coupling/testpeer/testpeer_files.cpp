#include "testpeer_files.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>

namespace dembridge::mbdyn::testpeer {

namespace {

bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

// Waits until ready() (sleeping sleep_s per try) or timeout_s; false on timeout.
template <class Ready>
bool wait_for(const PeerFiles& f, Ready ready) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(f.timeout_s);
  while (!ready()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::duration<double>(f.sleep_s));
  }
  return true;
}

void put(std::string& line, double v, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%s%.*e", line.empty() ? "" : " ", precision, v);
  line += buf;
}

}  // namespace

std::string write_out_file(const PeerFiles& f, const ElementShape& shape, const std::vector<NodeState>& nodes) {
  if (!wait_for(f, [&] { return !exists(f.out_path); }))
    return "output file \"" + f.out_path + "\" still present after " + std::to_string(f.timeout_s) + " s";
  std::string text = "# regular nodes\n";
  const bool matrix = shape.orientation == Orientation::Matrix;
  for (const NodeState& n : nodes) {
    std::string line = shape.labels ? std::to_string(n.label) : "";
    for (double v : n.x) put(line, v, f.precision);
    if (matrix)
      for (const auto& row : n.R)
        for (double v : row) put(line, v, f.precision);
    for (double v : n.v) put(line, v, f.precision);
    if (matrix)
      for (double v : n.w) put(line, v, f.precision);
    text += line + "\n";
  }
  const std::string tmp = f.out_path + ".tmp";
  {
    std::ofstream o(tmp, std::ios::trunc);
    o << text;
    if (!o) return "cannot write " + tmp;
  }
  if (std::rename(tmp.c_str(), f.out_path.c_str()) != 0) return "cannot rename " + tmp;
  return "";
}

std::string read_in_file(const PeerFiles& f, const ElementShape& shape, LoadsMessage& loads) {
  if (!wait_for(f, [&] { return exists(f.in_path); }))
    return "input file \"" + f.in_path + "\" missing after " + std::to_string(f.timeout_s) + " s";
  std::ifstream in(f.in_path);
  const bool moments = shape.orientation != Orientation::None;
  loads.labels.assign(shape.labels ? shape.nodes : 0, 0);
  loads.force.assign(shape.nodes, V3{0, 0, 0});
  loads.moment.assign(shape.nodes, V3{0, 0, 0});
  for (std::uint32_t i = 0; i < shape.nodes; ++i) {
    if (shape.labels && !(in >> loads.labels[i])) return "input file: no label for node " + std::to_string(i);
    for (double& v : loads.force[i])
      if (!(in >> v)) return "input file: short force line for node " + std::to_string(i);
    if (moments)
      for (double& v : loads.moment[i])
        if (!(in >> v)) return "input file: short moment line for node " + std::to_string(i);
  }
  in.close();
  ::unlink(f.in_path.c_str());  // `unlink`
  return "";
}

}  // namespace dembridge::mbdyn::testpeer
