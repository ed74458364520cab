// Per-torsion-spring state carried from step to step, plus the outputs of the last step (spec
// parmec-springs §7, §14). Plain data: the LAMMPS glue migrates it with part1's owner and writes it to
// restart files through pack()/unpack().
#pragma once

#include "spring_vec3.h"

namespace dembridge::torsion {

using springs::Vec3;

struct TorsionState {
  Vec3 angle{};         // ROLL, PITCH, YAW: integrated, initially 0 (fresh at creation: Q23)
  Vec3 torque_total{};  // TRQTOT_R/P/Y of the last step (spring + damper)
  Vec3 torque_spring{}; // TRQSPR_R/P/Y of the last step (spring only)
  Vec3 xdir{};          // XDIR_X/Y/Z: current x of the last step
  Vec3 zdir{};          // ZDIR_X/Y/Z: current z of the last step

  static constexpr int kPackedSize = 16;  // doubles written by pack() (15 used, 1 reserved)
  void pack(double* buf) const;
  void unpack(const double* buf);
};

}  // namespace dembridge::torsion
