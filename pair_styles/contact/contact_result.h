// What one contact contributes to the two atoms, plus values for per-contact output.
#pragma once

namespace dembridge::gran {

// R: double (one contact) or Lanes4 (four, lane_math.h)
template <class R> struct ContactResultT {
  R F[3] = {};   // total force on i (on j: -F)
  R Ti[3] = {};  // torque on i
  R Tj[3] = {};  // torque on j
  R Fn = {};     // normal force scalar along n (after damping and cohesion)
  R Ft[3] = {};  // tangential force on i
  R delta = {};  // overlap
};
using ContactResult = ContactResultT<double>;

}  // namespace dembridge::gran
