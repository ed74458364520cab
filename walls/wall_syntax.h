// The arguments of `fix wall/gran` (LIGGGHTS 3.x `model ...` grammar, and the 2.x style names
// wall/gran/<model>) parsed into one WallSpec. LAMMPS-free; throws gran::SyntaxError with a
// message naming the argument and what was expected (spec liggghts-walls §1).
#pragma once

#include "model_syntax.h"
#include "primitive_wall.h"

#include <string>
#include <vector>

namespace dembridge::walls {

struct WallSpec {
  gran::ModelDescription model;
  bool is_mesh = false;
  PrimitiveWall primitive;              // when !is_mesh
  std::vector<std::string> mesh_ids;    // when is_mesh, in `meshes` order
  int shear_dim = -1;                   // `shear x|y|z v` (primitive only)
  double shear_v = 0.0;
};

// style: "wall/gran" or a 2.x name "wall/gran/hooke/history" ...; args: the words after it.
// prefix: "fix ID wall/gran" for the messages.
WallSpec parse_wall_gran(const std::string &style, const std::vector<std::string> &args, const std::string &prefix);

// True for the style names this module handles with LIGGGHTS syntax.
bool is_liggghts_wall_style(const std::string &style);

// LAMMPS's built-in `fix wall/gran` syntax (fstyle Kn Kt ...): the plugin hands it to the built-in.
bool is_lammps_wall_syntax(const std::string &style, const std::vector<std::string> &args);

}  // namespace dembridge::walls
