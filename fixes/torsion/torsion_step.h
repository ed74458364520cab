// One evaluation of one torsion spring: angle integration, spring/damper torques, cone option
// (spec parmec-springs §7). Advances the state: call exactly once per time step.
#pragma once

#include "torsion_frame.h"
#include "torsion_law.h"
#include "torsion_state.h"

namespace dembridge::torsion {

struct TorsionStepInput {
  TorsionFrame frame;   // current_frame(reference, Λ1 at t_{n+1/2})
  Vec3 relative_omega{};// ω1 − ω2 (spatial, at t_n; ω2 = 0 for part2 = -1)
  double dt = 0.0;      // h
  Vec3 axis_inertia{};  // axis_inertias(...); read only if law.needs_axis_inertia()
};

struct TorsionTorque {
  Vec3 rate{};     // x·(ω1−ω2), y·(ω1−ω2), z·(ω1−ω2)
  Vec3 total{};    // roll, pitch, yaw components with damper (TRQTOT)
  Vec3 spring{};   // spring-only components (TRQSPR)
  Vec3 on_part1{}; // T_r x + T_p y + T_y z: apply to part1, the opposite to part2
};

TorsionTorque advance_torsion(const TorsionLaw& law, TorsionState& st, const TorsionStepInput& in);

}  // namespace dembridge::torsion
