// Constants of MBDyn's `external structural` socket protocol (spec mbdyn-protocol §2, §3).
// Everything on the wire is host-native: uint8 commands, uint32 flags/counts/labels, IEEE doubles.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace dembridge::mbdyn {

static_assert(sizeof(double) == 8, "MBDyn sends 8-byte IEEE doubles (spec §2, P6)");
static_assert(sizeof(std::uint32_t) == 4, "flags, counts and labels are uint32 (spec §2)");

// Command bytes (spec §3 table). Any other value is a protocol error.
enum class Command : std::uint8_t {
  RegularData = 2,               // tight iterate (MBDyn) / loads, not converged (peer)
  GotoNextStep = 4,              // peer: converged, keep previous loads, no payload
  Abort = 5,                     // end of simulation (MBDyn) / stop at end of step (peer)
  RegularDataAndGotoNextStep = 6,  // loose/start-up kinematics (MBDyn) / loads + converged (peer)
  Negotiation = 7,               // negotiation request (client)
  Ok = 8,                        // negotiation accepted (server)
};

// Negotiation flag bits (spec §3).
namespace flag {
constexpr std::uint32_t Modal = 0x0001;
constexpr std::uint32_t Nodal = 0x0002;
constexpr std::uint32_t ReferenceNode = 0x0004;
constexpr std::uint32_t Accelerations = 0x0008;
constexpr std::uint32_t Labels = 0x0010;
constexpr std::uint32_t RotationMask = 0x0F00;
// Reference-node rotation bits: set by libmbc, ignored by `external structural` (spec §3).
constexpr std::uint32_t ReferenceRotationMask = 0xF000;
}  // namespace flag

// MBDyn 1.7.3 reads a load payload with one recv(); 48 000 B arrived whole over Unix and TCP,
// larger payloads were split and failed (spec P2). Warn users above this.
constexpr std::size_t kLargestVerifiedLoadsPayload = 48000;

// Orientation formats; the values are the negotiation bits (spec §3).
enum class Rotation : std::uint32_t {
  None = 0x0000,
  OrientationVector = 0x0100,  // theta = angle * axis, radians
  OrientationMatrix = 0x0200,  // MBDyn's default; 9 doubles, column-major on the wire
  Euler123 = 0x0400,           // degrees, R = Rx(e1) Ry(e2) Rz(e3)
};

// Doubles per orientation entry: 9 matrix, 3 vector or Euler, 0 none (spec §4 "nR").
int rotation_doubles(Rotation r);
std::string rotation_name(Rotation r);
// Name of a command byte for error messages, e.g. "6 (regular data and goto next step)".
std::string command_name(std::uint8_t byte);
bool is_known_command(std::uint8_t byte);

}  // namespace dembridge::mbdyn
