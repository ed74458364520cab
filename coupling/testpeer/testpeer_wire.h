// MBDyn's half of the byte layouts (spec §2-§4), written independently of coupling/protocol:
// kinematics are serialised field by field in MBDyn's order, loads parsed back.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace dembridge::mbdyn::testpeer {

enum class Orientation { None, Vector, Matrix, Euler123 };
const char* orientation_keyword(Orientation o);  // MBDyn input keyword, e.g. "orientation matrix"

// The `external structural` element as MBDyn's input would declare it.
struct ElementShape {
  std::uint32_t nodes = 1;
  Orientation orientation = Orientation::Matrix;
  bool labels = false;
  bool accelerations = false;
  bool reference_node = false;
};

std::uint32_t negotiation_flags(const ElementShape& shape);

using Mat3 = std::array<std::array<double, 3>, 3>;  // m[row][col]
using V3 = std::array<double, 3>;

// One node's state as MBDyn holds it (global, or relative to the reference node).
struct NodeState {
  std::uint32_t label = 0;
  V3 x{}, v{}, w{}, a{}, wdot{};
  Mat3 R{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
};

struct LoadsMessage {
  std::uint32_t ref_label = 0;
  V3 ref_force{}, ref_moment{};
  std::vector<std::uint32_t> labels;
  std::vector<V3> force, moment;
};

// Payload after the command byte, MBDyn -> peer. ref is used only with a reference node.
std::vector<std::uint8_t> encode_kinematics_payload(const ElementShape& shape, const NodeState& ref,
                                                    const std::vector<NodeState>& nodes);
std::size_t loads_payload_size(const ElementShape& shape);
// Parses a loads payload; throws std::runtime_error when size is not loads_payload_size().
LoadsMessage decode_loads_payload(const ElementShape& shape, const std::uint8_t* data, std::size_t size);

// Orientation formats MBDyn writes (spec §4.3): radians rotation vector, Euler 1-2-3 degrees.
V3 rotation_vector_of(const Mat3& R);
V3 euler123_degrees_of(const Mat3& R);
Mat3 rotation_about_z(double angle);
Mat3 rotation_about_x(double angle);
Mat3 rotation_about_y(double angle);
Mat3 multiply(const Mat3& A, const Mat3& B);
Mat3 transpose(const Mat3& A);
V3 rotate_vector(const Mat3& A, const V3& v);

}  // namespace dembridge::mbdyn::testpeer
