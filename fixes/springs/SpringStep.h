// One force evaluation of one spring: state code dispatch, elastic law, dashpot, friction
// (spec parmec-springs §4.3, §5, §6). Advances the spring state: call exactly once per time step.
#pragma once

#include "SpringGeometry.h"
#include "SpringLaw.h"
#include "SpringState.h"
#include "Vec3.h"

namespace dembridge::springs {

struct SpringStepInput {
  double stroke0 = 0.0;            // reference_stroke0() of the spring
  double time = 0.0;               // t_n, argument of the offset curve
  double dt = 0.0;                 // step (kskn friction)
  double equivalent_mass = 0.0;    // EQM along frame.z; read only if law.needs_equivalent_mass()
  const SpringTable* unspring_unload = nullptr;  // the unload curve of code >= 0 (UNSPRING), else unused
};

struct SpringForce {
  double total = 0.0;    // F = elastic + dashpot (output F)
  double elastic = 0.0;  // SF
  double damping = 0.0;  // dashpot coefficient c used this step
  Vec3 friction{};       // friction force on part1
  Vec3 on_part1{};       // z F + friction: apply at p to part1 and the opposite at q to part2
};

SpringForce advance_spring(const SpringLaw& law, SpringState& st, const SpringFrame& frame, const SpringStepInput& in);

}  // namespace dembridge::springs
