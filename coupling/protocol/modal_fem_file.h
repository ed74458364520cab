// MBDyn's modal FEM data file (the `from file` argument of the modal joint): record groups
// opened by `** RECORD GROUP n, ...` lines, free-format values, other `**` lines are comments,
// `** END OF FILE` ends it. Read here for the shapes of the modes that cross the socket of
// `external modal`.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace dembridge::mbdyn {

// A malformed FEM file; the message starts with "FEM file '<path>' line <n>: ".
class FemFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct FemModel {
  std::string path;
  std::vector<std::string> node_labels;            // record group 2
  std::vector<std::array<double, 3>> node_xyz;     // record groups 5, 6, 7 (FEM frame)
  std::size_t num_modes = 0;                       // normal + attachment + constraint - rejected
  // record group 8 without the rejected modes: shapes[(mode * nodes + node) * 6 + k],
  // k = 0..2 translation, 3..5 rotation
  std::vector<double> shapes;
  std::vector<double> q0, qdot0;                   // groups 3, 4 (zeros when absent)
  std::vector<double> mass, stiffness, damping;    // groups 9, 10, 13 (num_modes^2, file order; empty when absent)

  std::size_t num_nodes() const { return node_labels.size(); }
  std::array<double, 3> translation(std::size_t mode, std::size_t node) const {
    const double* s = &shapes[(mode * num_nodes() + node) * 6];
    return {s[0], s[1], s[2]};
  }
  // Index of a FEM node label; throws FemFileError naming the label and the file otherwise.
  std::size_t node_index(const std::string& label) const;
};

// Reads and checks the file: group 1 first, each group at most once, groups 1, 2, 5, 6, 7 and 8
// present, every group with exactly its number of values, every value a number. Throws
// FemFileError naming the file, the line and what was expected.
FemModel read_fem_file(const std::string& path);
// The same from text (path only names it in errors).
FemModel parse_fem_text(const std::string& text, const std::string& path);

}  // namespace dembridge::mbdyn
