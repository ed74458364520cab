// What the files of fix parmec/spring share: the layout of a spring's record slot (FixParmecSpring::kSlot) and
// the small helpers of its loops and output.
#pragma once

#include "spring_state.h"
#include "spring_vec3.h"

namespace dembridge::spring_fix {

using springs::operator+;
using springs::operator-;
using springs::operator*;

constexpr int kState = springs::SpringState::kPackedSize;
constexpr int kForce = 1 + kState;  // offset of the stored force in a slot
constexpr int kValid = kForce + 3;  // 1 once the spring has committed a step
constexpr int kCols = 8;            // id LENGTH STROKE F SF FF SS EQM

inline springs::Vec3 vec(const double *a) { return {a[0], a[1], a[2]}; }
inline bool zero(const springs::Vec3 &a) { return a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0; }

// LENGTH STROKE F SF FF SS of a spring state: the output columns 2-7 and the history columns.
inline void state_columns(const springs::SpringState &st, double *out)
{
  out[0] = st.length;
  out[1] = st.stroke;
  out[2] = st.force_total;
  out[3] = st.force_elastic;
  out[4] = st.friction_force;
  out[5] = st.code;
}

}  // namespace dembridge::spring_fix
