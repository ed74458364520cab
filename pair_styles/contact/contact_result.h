// What one contact contributes to the two atoms, plus values for per-contact output.
#pragma once

namespace dembridge::gran {

struct ContactResult {
  double F[3] = {0, 0, 0};   // total force on i (on j: -F)
  double Ti[3] = {0, 0, 0};  // torque on i
  double Tj[3] = {0, 0, 0};  // torque on j
  double Fn = 0;             // normal force scalar along n (after damping and cohesion)
  double Ft[3] = {0, 0, 0};  // tangential force on i
  double delta = 0;          // overlap
};

}  // namespace dembridge::gran
