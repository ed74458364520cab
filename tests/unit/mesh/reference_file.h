// Reader of the *.ref files written by tests/data/liggghts-walls/mesh/gen_mesh_geometry_ref.py:
// lines of whitespace-separated tokens, doubles as C99 hex floats.
#pragma once

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace dembridge::mesh::test {

inline std::string data_path(const std::string &name) { return std::string(DEMBRIDGE_MESH_DATA) + "/" + name; }

inline std::vector<std::vector<std::string>> read_ref(const std::string &name)
{
  std::ifstream in(data_path(name));
  std::vector<std::vector<std::string>> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::vector<std::string> tok;
    std::string w;
    while (ls >> w) tok.push_back(w);
    lines.push_back(tok);
  }
  return lines;
}

inline double num(const std::string &s) { return std::strtod(s.c_str(), nullptr); }

}  // namespace dembridge::mesh::test
