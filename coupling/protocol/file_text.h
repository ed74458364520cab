// MBDyn's file communicator for `external structural`: the text of the OUT file MBDyn writes
// (kinematics) and of the IN file the peer writes (loads). OUT: comment lines (`# regular nodes`),
// then one line per point: [label] x y z [R row by row 9 | theta 3 | Euler 1-2-3 degrees 3]
// vx vy vz [wx wy wz] [a 3 [wdot 3] with accelerations]. IN: one line per point: [label] Fx Fy Fz
// [Mx My Mz unless orientation none]. Global frame; no reference node (not supported here).
#pragma once

#include <string>

#include "nodal_config.h"
#include "nodal_message.h"

namespace dembridge::mbdyn {

// Parses an OUT file's text into k (shaped for config as decode_kinematics leaves it; matrices
// converted to the wire's column-major order). Throws MalformedMessageError naming what (the file),
// the line and what was expected: a wrong number of point lines or of numbers on one, a value that
// is not a finite number, a label that is not an integer.
void parse_kinematics_text(const NodalConfig& config, const std::string& text, const std::string& what,
                           Kinematics& k);
// The OUT text of k, MBDyn's way (`%.<precision>e`), for the test peer and the tests.
std::string format_kinematics_text(const NodalConfig& config, const Kinematics& k, int precision);

// The IN text of loads (labels from labels, in that order), `%.<precision>e`.
std::string format_loads_text(const NodalConfig& config, const Loads& loads, const std::vector<std::uint32_t>& labels,
                              int precision);
// Parses an IN file's text (the test peer's side). Throws MalformedMessageError as above.
Loads parse_loads_text(const NodalConfig& config, const std::string& text, const std::string& what);

}  // namespace dembridge::mbdyn
