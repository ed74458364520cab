#include "torsion_law.h"

#include <cmath>
#include <stdexcept>

namespace dembridge::torsion {

namespace {
const char* const kAxisName[3] = {"roll", "pitch", "yaw"};
}

Cone parse_cone(const std::vector<std::string>& names) {
  if (names.empty()) return Cone::None;
  if (names.size() < 2 || names.size() > 3)
    throw std::invalid_argument("TORSION_SPRING: cone must name 2 or 3 of roll, pitch, yaw (got " +
                                std::to_string(names.size()) + " names)");
  bool used[3] = {false, false, false};
  for (const auto& n : names) {
    int a = -1;
    for (int i = 0; i < 3; ++i)
      if (n == kAxisName[i]) a = i;
    if (a < 0) throw std::invalid_argument("TORSION_SPRING: unknown cone name '" + n + "' (expected roll, pitch or yaw)");
    if (used[a]) throw std::invalid_argument("TORSION_SPRING: cone name '" + n + "' given twice");
    used[a] = true;
  }
  if (used[kRoll] && used[kPitch] && used[kYaw]) return Cone::RollPitchYaw;
  if (used[kRoll] && used[kPitch]) return Cone::RollPitch;
  if (used[kRoll] && used[kYaw]) return Cone::RollYaw;
  return Cone::PitchYaw;
}

const char* cone_name(Cone c) {
  switch (c) {
    case Cone::RollPitch: return "(roll, pitch)";
    case Cone::RollYaw: return "(roll, yaw)";
    case Cone::PitchYaw: return "(pitch, yaw)";
    case Cone::RollPitchYaw: return "(roll, pitch, yaw)";
    default: return "none";
  }
}

bool in_cone(Cone c, int axis) {
  switch (c) {
    case Cone::RollPitch: return axis == kRoll || axis == kPitch;
    case Cone::RollYaw: return axis == kRoll || axis == kYaw;
    case Cone::PitchYaw: return axis == kPitch || axis == kYaw;
    case Cone::RollPitchYaw: return true;
    default: return false;
  }
}

int leading_axis(Cone c) { return c == Cone::PitchYaw ? kPitch : kRoll; }

void TorsionLaw::validate() const {
  for (int a = 0; a < 3; ++a) {
    const AxisLaw& l = axis[a];
    const std::string d = std::string("d") + kAxisName[a];
    if (l.damper && l.ratio)
      throw std::invalid_argument("TORSION_SPRING: " + d + " is either a table or a critical damping ratio, not both");
    if (l.ratio && !(std::isfinite(*l.ratio) && *l.ratio >= 0.0))
      throw std::invalid_argument("TORSION_SPRING: critical damping ratio " + d + " must be finite and >= 0");
  }
  if (cone != Cone::None) {
    const int lead = leading_axis(cone);
    const AxisLaw& l = axis[lead];
    if (!l.spring && !l.damper && !l.ratio)
      throw std::invalid_argument(std::string("TORSION_SPRING: cone ") + cone_name(cone) + " uses the curves of " +
                                  kAxisName[lead] + ": give k" + kAxisName[lead] + " or d" + kAxisName[lead]);
  }
}

bool TorsionLaw::needs_axis_inertia() const {
  for (int a = 0; a < 3; ++a) {
    if (cone != Cone::None && in_cone(cone, a) && a != leading_axis(cone)) continue;  // its curves are unused
    if (axis[a].ratio) return true;
  }
  return false;
}

}  // namespace dembridge::torsion
