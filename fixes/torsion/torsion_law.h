// Constant parameters of one torsion spring: roll/pitch/yaw spring tables, dampers (table or critical
// ratio) and the cone option (spec parmec-springs §7). Tables are owned by the caller (registry) and
// must outlive the law.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "spring_table.h"

namespace dembridge::torsion {

enum Axis : int { kRoll = 0, kPitch = 1, kYaw = 2 };

struct AxisLaw {
  const springs::SpringTable* spring = nullptr;  // torque vs angle; null = Parmec's default ≡ 0
  const springs::SpringTable* damper = nullptr;  // torque vs angle rate; null = none
  std::optional<double> ratio;                   // critical damping ratio ζ >= 0 instead of a damper table
  bool given() const { return spring || damper || ratio; }
};

// Cone constraint in (roll, pitch, yaw) angle space (spec §7). The name order does not matter:
// ('roll','pitch') == ('pitch','roll').
enum class Cone { None, RollPitch, RollYaw, PitchYaw, RollPitchYaw };

// Parses a tuple of 2 or 3 distinct names from {roll, pitch, yaw}; an empty list is Cone::None.
// Throws std::invalid_argument naming the offending name (unknown, repeated, wrong count).
Cone parse_cone(const std::vector<std::string>& names);
const char* cone_name(Cone c);
// Axes taking part in the cone and its leading axis (first of roll, pitch, yaw among them): the curves of
// the leading axis are the ones used (spec §7).
bool in_cone(Cone c, int axis);
int leading_axis(Cone c);

struct TorsionLaw {
  AxisLaw axis[3];  // kRoll, kPitch, kYaw
  Cone cone = Cone::None;

  // Throws std::invalid_argument naming the rule: damper given both as a table and as a ratio, negative
  // or non-finite ratio, a cone whose leading axis has neither a spring nor a damper curve.
  void validate() const;
  // Axis inertias are needed only if some damper that is actually used is a ratio (spec §7).
  bool needs_axis_inertia() const;
};

}  // namespace dembridge::torsion
