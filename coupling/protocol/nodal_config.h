// What the MBDyn element exchanges: number of points and the optional blocks. Determines the
// negotiation flags and every message length (spec §3, §4).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "wire_format.h"

namespace dembridge::mbdyn {

struct NodalConfig {
  std::uint32_t num_points = 0;                      // N: node entries, not the reference node
  Rotation rotation = Rotation::OrientationMatrix;  // MBDyn's default (spec §4.4, P12)
  bool accelerations = false;
  bool labels = false;
  bool reference_node = false;
  // MBDyn's `external structural mapping` with `reference node` (points: orientation none): the
  // reference record carries the rotation chosen by the element's `orientation` (here
  // reference_rotation, sent << 4 in the flags), always the angular velocity, no pad after its
  // label; its loads record is always F0 and M0 (MBDyn's StructMappingExtForce).
  bool mapping_reference = false;
  Rotation reference_rotation = Rotation::None;

  // Flags sent in the negotiation. The reference-node rotation bits are left 0: external
  // structural ignores them and the verified refnode example is 0x216 (spec §3).
  std::uint32_t flags() const;
  // Inverse of flags(); throws NegotiationError for modal, non-nodal or unknown rotation bits.
  static NodalConfig from_flags(std::uint32_t flags, std::uint32_t num_points);

  bool has_rotation() const { return rotation != Rotation::None; }
  // The reference record's rotation, and whether it has an angular velocity and a moment.
  Rotation record_rotation() const { return mapping_reference ? reference_rotation : rotation; }
  bool record_has_omega() const { return mapping_reference || has_rotation(); }
  int rotation_doubles() const;  // nR
  // Doubles per point in the kinematics: x, orientation, v, [omega], [a, [omega_dot]].
  std::size_t point_kinematics_doubles() const;
  // Label block of N + (N mod 2) uint32 values, so doubles stay 8-aligned (spec §2).
  std::size_t label_block_bytes() const;
  std::size_t reference_kinematics_bytes() const;  // 0 without reference node
  std::size_t reference_loads_bytes() const;       // 0 without reference node
  std::size_t kinematics_payload_bytes() const;    // after the command byte (spec §4.1)
  std::size_t loads_payload_bytes() const;         // after a 2 or 6 command byte (spec §4.2)

  bool operator==(const NodalConfig& o) const;
  bool operator!=(const NodalConfig& o) const { return !(*this == o); }
  // e.g. "N=2, orientation matrix, labels yes, accelerations no, reference node no"
  std::string describe() const;
};

}  // namespace dembridge::mbdyn
