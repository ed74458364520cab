// The two payloads of `external structural`: kinematics MBDyn -> peer and loads peer -> MBDyn
// (spec §4). Arrays are kept structure-of-arrays exactly as on the wire.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nodal_config.h"
#include "wire_format.h"

namespace dembridge::mbdyn {

using Vec3 = std::array<double, 3>;
// Row-major 3x3 matrix: m[3 * row + col]. (The wire order is column-major, spec §2.)
using Matrix3 = std::array<double, 9>;

// Absolute state of the reference node (spec §4.1 reference record).
struct ReferenceKinematics {
  std::uint32_t label = 0;            // only with labels
  Vec3 x{};
  std::array<double, 9> orientation{};  // first nR values, wire format
  Vec3 v{}, omega{}, a{}, omega_dot{};
};

// One kinematics message. Without reference node everything is global; with it, points are
// relative to the reference node and in its frame (spec §4.3).
struct Kinematics {
  Command command = Command::RegularDataAndGotoNextStep;  // 2 (tight iterate) or 6
  Rotation rotation = Rotation::OrientationMatrix;
  Rotation reference_rotation = Rotation::OrientationMatrix;  // the reference record's
  bool has_reference = false;
  ReferenceKinematics reference;
  std::vector<std::uint32_t> labels;  // N node labels (empty without labels)
  std::vector<double> x;              // 3N
  std::vector<double> orientation;    // nR * N, wire format (matrix column-major)
  std::vector<double> v;              // 3N
  std::vector<double> omega;          // 3N, empty without rotation
  std::vector<double> a;              // 3N, empty without accelerations
  std::vector<double> omega_dot;      // 3N, only with accelerations and rotation

  std::size_t num_points() const { return x.size() / 3; }
  Vec3 position(std::size_t i) const { return {x[3 * i], x[3 * i + 1], x[3 * i + 2]}; }
  Vec3 velocity(std::size_t i) const { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }
  // Orientation of point i as a row-major matrix mapping local to global components, converted
  // from whatever format was negotiated (identity for Rotation::None).
  Matrix3 rotation_matrix(std::size_t i) const;
  // The same for the reference node (absolute, global frame).
  Matrix3 reference_rotation_matrix() const;
};

// Loads for one answer (spec §4.2). Forces and moments are global (or in the reference node's
// frame when a reference node is used); moments are about the point.
struct Loads {
  Loads() = default;
  explicit Loads(const NodalConfig& config);  // zero loads of the right sizes

  std::uint32_t reference_label = 0;  // echoed with labels and reference node
  Vec3 reference_force{};
  Vec3 reference_moment{};
  std::vector<std::uint32_t> labels;  // echo of the received labels, same order (spec P10)
  std::vector<double> force;          // 3N
  std::vector<double> moment;         // 3N; must be empty or zero-sized without rotation

  void set_force(std::size_t i, const Vec3& f);
  void set_moment(std::size_t i, const Vec3& m);
};

// One piece of a payload's wire layout: size bytes at data, the pieces back to back (spec §2).
// data == nullptr is a pad: ignored on receipt, zero when sent. The layouts are written once,
// as lists of these pieces, and both decoding and encoding walk them. (A transport can also
// read a message straight into them with one recvmsg; for MBDyn's messages that measured slower
// than one contiguous recvmsg plus these copies, issue 12 P5, so the session does not.)
struct WireSpan {
  void* data;
  std::size_t size;
};

// The kinematics payload as pieces of k's own storage. k is first shaped for config: its vectors
// sized (capacity kept: no allocation after the first message), absent fields emptied, the
// reference record zeroed, as decode_kinematics leaves them. k.command is left to the caller.
// Reading the payload into the pieces, then validate_kinematics, is decode_kinematics_into.
void kinematics_wire_spans(const NodalConfig& config, Kinematics& k, std::vector<WireSpan>& out);
// The checks of a decoded payload: every value finite; throws MalformedMessageError naming the
// field, point and label of the first that is not.
void validate_kinematics(const NodalConfig& config, const Kinematics& k);
// Decodes a kinematics payload (the bytes after the command byte). Throws MalformedMessageError
// if the size differs from config.kinematics_payload_bytes() or a value is not finite (naming the
// field, point and label).
Kinematics decode_kinematics(const NodalConfig& config, Command command,
                             const std::uint8_t* payload, std::size_t size);
// The same into an existing Kinematics, reusing its storage (per-message path of the session).
void decode_kinematics_into(const NodalConfig& config, Command command, const std::uint8_t* payload,
                            std::size_t size, Kinematics& k);

// Decodes a whole kinematics message (command byte + payload), as a fuzzing entry point.
Kinematics decode_kinematics_message(const NodalConfig& config, const std::uint8_t* bytes,
                                     std::size_t size);

// Builds one complete message, command byte then payload, ready for a single write (spec P2).
// command must be 2 or 6 (a payload follows); throws std::invalid_argument on wrong sizes and
// MalformedMessageError on non-finite loads.
std::vector<std::uint8_t> encode_loads(const NodalConfig& config, Command command,
                                       const Loads& loads);
// The same into out (resized to the message, its capacity kept).
void encode_loads_into(const NodalConfig& config, Command command, const Loads& loads,
                       std::vector<std::uint8_t>& out);
// The same with the labels the message carries given apart from loads (with labels: MBDyn's
// own, echoed, spec P10; read only with config.labels): the session's per-message path, which
// then neither copies loads nor allocates.
void encode_loads_into(const NodalConfig& config, Command command, const Loads& loads,
                       const std::vector<std::uint32_t>& labels, const std::uint32_t* reference_label,
                       std::vector<std::uint8_t>& out);

// Orientation conversions used by Kinematics::rotation_matrix (spec §4.3).
// Wire: R11 R21 R31 R12 R22 R32 R13 R23 R33 (spec §2, verified). Inline: it runs per point and message.
inline Matrix3 matrix_from_wire_column_major(const double* w) {
  return {w[0], w[3], w[6], w[1], w[4], w[7], w[2], w[5], w[8]};
}
Matrix3 matrix_from_orientation_vector(const double* theta);  // radians
Matrix3 matrix_from_euler123_degrees(const double* e);        // R = Rx(e1) Ry(e2) Rz(e3)

}  // namespace dembridge::mbdyn
