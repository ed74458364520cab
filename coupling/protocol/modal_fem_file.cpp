#include "modal_fem_file.h"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace dembridge::mbdyn {

namespace {

struct Token {
  std::string text;
  std::size_t line;
};

struct Group {
  long number = 0;
  std::size_t line = 0;  // of its header
  std::vector<Token> tokens;
};

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& what) {
  throw FemFileError("FEM file '" + path + "' line " + std::to_string(line) + ": " + what);
}

// Splits the text into record groups; values outside any group are refused.
std::vector<Group> split_groups(const std::string& text, const std::string& path) {
  std::vector<Group> groups;
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (starts_with(line, "** END OF FILE")) break;
    if (starts_with(line, "** RECORD GROUP ")) {
      const char* digits = line.c_str() + 16;
      char* end = nullptr;
      const long number = std::strtol(digits, &end, 10);
      if (end == digits) fail(path, n, "expected a record group number after '** RECORD GROUP', got '" + line + "'");
      groups.push_back({number, n, {}});
      continue;
    }
    if (starts_with(line, "**")) continue;  // comment (a mode's header in group 8)
    std::istringstream words(line);
    for (std::string w; words >> w;) {
      if (groups.empty()) fail(path, n, "expected '** RECORD GROUP 1' before any value, got '" + w + "'");
      groups.back().tokens.push_back({w, n});
    }
  }
  return groups;
}

double number(const Token& t, const std::string& path) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.text.c_str(), &end);
  if (end == t.text.c_str() || *end != '\0' || errno == ERANGE)
    fail(path, t.line, "expected a number, got '" + t.text + "'");
  return v;
}

std::size_t count(const Token& t, const std::string& path, const char* what) {
  char* end = nullptr;
  const long v = std::strtol(t.text.c_str(), &end, 10);
  if (end == t.text.c_str() || *end != '\0' || v < 0)
    fail(path, t.line, std::string("expected a non-negative integer for ") + what + ", got '" + t.text + "'");
  return static_cast<std::size_t>(v);
}

void expect_size(const Group& g, std::size_t n, const std::string& what, const std::string& path) {
  if (g.tokens.size() != n)
    fail(path, g.line, "RECORD GROUP " + std::to_string(g.number) + " has " + std::to_string(g.tokens.size()) +
                           " values, expected " + std::to_string(n) + " (" + what + ")");
}

std::vector<double> numbers(const Group& g, std::size_t from, const std::string& path) {
  std::vector<double> v;
  for (std::size_t i = from; i < g.tokens.size(); ++i) v.push_back(number(g.tokens[i], path));
  return v;
}

}  // namespace

std::size_t FemModel::node_index(const std::string& label) const {
  for (std::size_t i = 0; i < node_labels.size(); ++i)
    if (node_labels[i] == label) return i;
  throw FemFileError("FEM file '" + path + "': no FEM node labelled '" + label + "'");
}

FemModel parse_fem_text(const std::string& text, const std::string& path) {
  const std::vector<Group> groups = split_groups(text, path);
  if (groups.empty() || groups[0].number != 1)
    fail(path, groups.empty() ? 1 : groups[0].line, "expected '** RECORD GROUP 1' (the header) first");
  FemModel m;
  m.path = path;
  const Group& header = groups[0];
  expect_size(header, 6, "REVISION NODE NORMAL ATTACHMENT CONSTRAINT REJECTED", path);
  const std::size_t nodes = count(header.tokens[1], path, "NODE");
  const std::size_t normal = count(header.tokens[2], path, "NORMAL");
  const std::size_t attachment = count(header.tokens[3], path, "ATTACHMENT");
  const std::size_t constraint = count(header.tokens[4], path, "CONSTRAINT");
  const std::size_t rejected = count(header.tokens[5], path, "REJECTED");
  if (nodes == 0) fail(path, header.tokens[1].line, "expected at least one FEM node, got 0");
  if (rejected > normal + attachment + constraint || normal + attachment + constraint == rejected)
    fail(path, header.tokens[5].line, "expected fewer rejected modes than modes, got " + std::to_string(rejected) +
                                          " rejected of " + std::to_string(normal + attachment + constraint));
  m.num_modes = normal + attachment + constraint - rejected;
  const std::size_t modes = m.num_modes;
  const std::string dims = std::to_string(modes) + " modes, " + std::to_string(nodes) + " nodes";
  m.q0.assign(modes, 0.0);
  m.qdot0.assign(modes, 0.0);
  m.node_xyz.assign(nodes, {0.0, 0.0, 0.0});
  bool seen[14] = {};
  seen[1] = true;
  for (std::size_t gi = 1; gi < groups.size(); ++gi) {
    const Group& g = groups[gi];
    if (g.number < 2 || g.number > 13)
      fail(path, g.line, "expected record groups 1 to 13, got RECORD GROUP " + std::to_string(g.number));
    if (seen[g.number]) fail(path, g.line, "RECORD GROUP " + std::to_string(g.number) + " given twice");
    seen[g.number] = true;
    switch (g.number) {
      case 2:
        expect_size(g, nodes, "one label per FEM node, " + dims, path);
        for (const Token& t : g.tokens) m.node_labels.push_back(t.text);
        break;
      case 3: expect_size(g, modes, "one per mode, " + dims, path); m.q0 = numbers(g, 0, path); break;
      case 4: expect_size(g, modes, "one per mode, " + dims, path); m.qdot0 = numbers(g, 0, path); break;
      case 5: case 6: case 7: {
        expect_size(g, nodes, "one coordinate per FEM node, " + dims, path);
        const std::vector<double> c = numbers(g, 0, path);
        for (std::size_t i = 0; i < nodes; ++i) m.node_xyz[i][g.number - 5] = c[i];
        break;
      }
      case 8: {
        expect_size(g, (modes + rejected) * nodes * 6,
                    "6 per FEM node and mode, rejected modes first, " + dims + ", " + std::to_string(rejected) + " rejected",
                    path);
        m.shapes = numbers(g, rejected * nodes * 6, path);
        break;
      }
      case 9: expect_size(g, modes * modes, "modes x modes, " + dims, path); m.mass = numbers(g, 0, path); break;
      case 10: expect_size(g, modes * modes, "modes x modes, " + dims, path); m.stiffness = numbers(g, 0, path); break;
      case 11: expect_size(g, nodes * 6, "6 per FEM node, " + dims, path); numbers(g, 0, path); break;
      case 12: expect_size(g, 13, "mass, centre of mass 3, inertia 9", path); numbers(g, 0, path); break;
      case 13: expect_size(g, modes * modes, "modes x modes, " + dims, path); m.damping = numbers(g, 0, path); break;
    }
  }
  const std::size_t last_line = groups.back().line;
  for (int needed : {2, 5, 6, 7, 8})
    if (!seen[needed]) fail(path, last_line, "RECORD GROUP " + std::to_string(needed) + " missing");
  return m;
}

FemModel read_fem_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw FemFileError("FEM file '" + path + "': cannot be opened");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_fem_text(text.str(), path);
}

}  // namespace dembridge::mbdyn
