// MBDyn's modal data file (the FEM file of a `modal` joint, `from file`): `** RECORD GROUP n`
// headers, other `**` lines are comments, values whitespace separated. Read here: 1 header
// (revision, FEM nodes, normal, attachment, constraint, rejected modes), 2 node labels, 3/4 initial
// q, q', 5/6/7 node x/y/z, 8 mode shapes (per mode, per node: 3 translations, 3 rotations),
// 9 modal mass, 10 modal stiffness, 11 lumped masses (per node m m m Jx Jy Jz), 13 modal damping.
// The test peer builds the inertia invariants from record 11 (MBDyn does the same when it is
// given), so record 11 is required; records 12 and 14-18 (given inertia/invariants) are refused.
#pragma once

#include <string>
#include <vector>

#include "testpeer_wire.h"

namespace dembridge::mbdyn::testpeer {

struct ModalFemData {
  std::vector<std::string> labels;  // FEM node labels
  std::vector<V3> position;         // per node
  std::vector<double> node_mass;    // per node
  std::vector<V3> node_inertia;     // per node, diagonal
  // shape_t[m][n], shape_r[m][n]: mode m at node n
  std::vector<std::vector<V3>> shape_t, shape_r;
  std::vector<double> mass, stiffness, damping;  // M x M, row by row as MBDyn stores them
  std::vector<double> q0, qdot0;
  std::size_t modes() const { return shape_t.size(); }
};

// Throws std::runtime_error naming the file and the record on bad input.
ModalFemData read_modal_fem_file(const std::string& path);

}  // namespace dembridge::mbdyn::testpeer
