// A body carried by MBDyn's modal node and deformed by the modes of its modal joint: the points
// (mesh vertices or atoms) sit on FEM nodes of the modal FEM file, and
//   x_v = x_n + R (X_v + sum_m q_m Phi_m(v)),   v_v = v_n + omega x (x_v - x_n) + R sum_m qdot_m Phi_m(v),
// with X_v the point's rest position relative to the modal node in the FEM frame. Loads f_v on the
// points become the answer of `external modal`: F = sum f_v, M = sum (x_v - x_n) x f_v (global,
// about the modal node) and p_m = sum_v Phi_m(v) . (R^T f_v).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "modal_fem_file.h"
#include "modal_message.h"

namespace dembridge::mbdyn {

struct ModalBody {
  std::size_t num_modes = 0;
  std::vector<std::array<double, 3>> rest;  // X_v, FEM frame, relative to the modal node
  std::vector<std::size_t> fem_node;        // the FEM node each point sits on
  std::vector<double> shapes;               // translation of mode m at point v: shapes[(m * P + v) * 3 + k]

  std::size_t num_points() const { return rest.size(); }
};

// The FEM model restricted to the element's modes: modes_1based lists them (MBDyn's `list`), or
// empty for the first `element_modes`. Throws std::invalid_argument naming the FEM file when it
// has fewer modes, a listed mode does not exist or is repeated, or the list has not
// element_modes entries.
FemModel select_modes(const FemModel& fem, std::size_t element_modes, const std::vector<int>& modes_1based);

// Puts each point (given in the FEM frame) on the FEM node within tolerance of it, the modal node
// being at FEM node `origin_label` (MBDyn's `origin node`; "" = the FEM frame's origin). Throws
// std::invalid_argument naming the point, its nearest FEM node and the distance otherwise.
ModalBody map_points_to_fem_nodes(const FemModel& fem, const std::vector<std::array<double, 3>>& points,
                                  const std::string& origin_label, double tolerance);

// Positions and velocities (3P each, global) for one kinematics message (type all). Throws
// std::invalid_argument if the message has not the body's number of modes.
void modal_point_states(const ModalBody& body, const ModalKinematics& k, std::vector<double>& x,
                        std::vector<double>& v);

// The answer for forces f (3P, global) on the points at positions x (3P, from modal_point_states).
ModalLoads project_modal_loads(const ModalBody& body, const ModalKinematics& k, const std::vector<double>& x,
                               const std::vector<double>& f);

}  // namespace dembridge::mbdyn
