// What one contact contributes to the two atoms, plus values for per-contact output.
#pragma once

namespace dembridge::gran {

struct ContactResult {
  double F[3];   // total force on i (on j: -F)
  double Ti[3];  // torque on i
  double Tj[3];  // torque on j
  double Fn;     // normal force scalar along n (after damping and cohesion)
  double Ft[3];  // tangential force on i
  double delta;  // overlap
};

}  // namespace dembridge::gran
