#include "nodal_config.h"

#include <sstream>

#include "protocol_error.h"

namespace dembridge::mbdyn {

std::uint32_t NodalConfig::flags() const {
  std::uint32_t f = flag::Nodal | static_cast<std::uint32_t>(rotation);
  if (reference_node) f |= flag::ReferenceNode;
  if (accelerations) f |= flag::Accelerations;
  if (labels) f |= flag::Labels;
  if (mapping_reference) f |= static_cast<std::uint32_t>(reference_rotation) << 4;
  return f;
}

NodalConfig NodalConfig::from_flags(std::uint32_t flags, std::uint32_t num_points) {
  std::ostringstream why;
  if (flags & flag::Modal) why << "modal bit 0x1 set (external modal is not supported); ";
  if (!(flags & flag::Nodal)) why << "nodal bit 0x2 missing; ";
  const std::uint32_t known = flag::Modal | flag::Nodal | flag::ReferenceNode |
                              flag::Accelerations | flag::Labels | flag::RotationMask |
                              flag::ReferenceRotationMask;
  if (flags & ~known) why << "unknown bits 0x" << std::hex << (flags & ~known) << std::dec << "; ";
  NodalConfig c;
  c.num_points = num_points;
  c.reference_node = flags & flag::ReferenceNode;
  c.accelerations = flags & flag::Accelerations;
  c.labels = flags & flag::Labels;
  const std::uint32_t rot = flags & flag::RotationMask;
  switch (rot) {
    case 0x000: c.rotation = Rotation::None; break;
    case 0x100: c.rotation = Rotation::OrientationVector; break;
    case 0x200: c.rotation = Rotation::OrientationMatrix; break;
    case 0x400: c.rotation = Rotation::Euler123; break;
    default: why << "rotation bits 0x" << std::hex << rot << std::dec
                 << " are not one of 0x0, 0x100, 0x200, 0x400; ";
  }
  const std::string problems = why.str();
  if (!problems.empty()) {
    std::ostringstream msg;
    msg << "invalid negotiation flags 0x" << std::hex << flags << std::dec << ": " << problems;
    throw NegotiationError(msg.str());
  }
  return c;
}

int NodalConfig::rotation_doubles() const { return mbdyn::rotation_doubles(rotation); }

std::size_t NodalConfig::point_kinematics_doubles() const {
  const std::size_t rot = has_rotation() ? 1 : 0;
  std::size_t n = 3 + rotation_doubles() + 3 + 3 * rot;
  if (accelerations) n += 3 + 3 * rot;
  return n;
}

std::size_t NodalConfig::label_block_bytes() const {
  if (!labels) return 0;
  return 4 * (static_cast<std::size_t>(num_points) + num_points % 2);
}

std::size_t NodalConfig::reference_kinematics_bytes() const {
  if (!reference_node) return 0;
  if (!mapping_reference) return (labels ? 8 : 0) + 8 * point_kinematics_doubles();
  return (labels ? 4 : 0) + 8 * (3 + mbdyn::rotation_doubles(reference_rotation) + 6 + (accelerations ? 6 : 0));
}

std::size_t NodalConfig::reference_loads_bytes() const {
  if (!reference_node) return 0;
  if (mapping_reference) return (labels ? 4 : 0) + 8 * 6;
  return (labels ? 8 : 0) + 8 * (has_rotation() ? 6 : 3);
}

std::size_t NodalConfig::kinematics_payload_bytes() const {
  std::size_t n = reference_kinematics_bytes();
  if (num_points > 0) n += label_block_bytes() + 8 * num_points * point_kinematics_doubles();
  return n;
}

std::size_t NodalConfig::loads_payload_bytes() const {
  std::size_t n = reference_loads_bytes();
  if (num_points > 0) n += label_block_bytes() + 8 * num_points * (has_rotation() ? 6 : 3);
  return n;
}

bool NodalConfig::operator==(const NodalConfig& o) const {
  return num_points == o.num_points && rotation == o.rotation &&
         accelerations == o.accelerations && labels == o.labels &&
         reference_node == o.reference_node && mapping_reference == o.mapping_reference &&
         (!mapping_reference || reference_rotation == o.reference_rotation);
}

std::string NodalConfig::describe() const {
  std::ostringstream s;
  s << "N=" << num_points << ", " << (has_rotation() ? "" : "orientation ") << rotation_name(rotation)
    << ", labels "
    << (labels ? "yes" : "no") << ", accelerations " << (accelerations ? "yes" : "no")
    << ", reference node " << (reference_node ? "yes" : "no");
  if (mapping_reference) s << " (structural mapping, reference " << rotation_name(reference_rotation) << ")";
  return s.str();
}

}  // namespace dembridge::mbdyn
