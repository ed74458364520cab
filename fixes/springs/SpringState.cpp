#include "SpringState.h"

namespace dembridge::springs {

SpringState SpringState::initial(const SpringLaw& law, bool inactive) {
  SpringState s;
  s.yield_comp = law.ylim_comp;
  s.yield_tens = law.ylim_tens;
  s.code = inactive ? kZeroForce : kRegular;
  return s;
}

// Every field is stored as a double; ints and flags are exact in a double, so pack/unpack is lossless.
void SpringState::pack(double* b) const {
  b[0] = stroke;
  b[1] = stroke_comp;
  b[2] = stroke_tens;
  b[3] = yield_comp;
  b[4] = yield_tens;
  b[5] = force_elastic;
  b[6] = tangent_stiffness;
  for (int i = 0; i < 3; ++i) b[7 + i] = friction_disp[i];
  for (int i = 0; i < 3; ++i) b[10 + i] = direction[i];
  b[13] = length;
  b[14] = force_total;
  b[15] = friction_force;
  b[16] = yielded ? 1.0 : 0.0;
  b[17] = unloading ? 1.0 : 0.0;
  b[18] = static_cast<double>(code);
  b[19] = 0.0;  // reserved (keeps the record size stable for later fields)
}

void SpringState::unpack(const double* b) {
  stroke = b[0];
  stroke_comp = b[1];
  stroke_tens = b[2];
  yield_comp = b[3];
  yield_tens = b[4];
  force_elastic = b[5];
  tangent_stiffness = b[6];
  for (int i = 0; i < 3; ++i) friction_disp[i] = b[7 + i];
  for (int i = 0; i < 3; ++i) direction[i] = b[10 + i];
  length = b[13];
  force_total = b[14];
  friction_force = b[15];
  yielded = b[16] != 0.0;
  unloading = b[17] != 0.0;
  code = static_cast<int>(b[18]);
}

}  // namespace dembridge::springs
