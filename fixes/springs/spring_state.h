// Per-spring state carried from step to step (spec parmec-springs §4, §6, §14). Plain data so that the
// LAMMPS glue can migrate it with the owning atom and write it to restart files via pack()/unpack().
#pragma once

#include "spring_law.h"
#include "spring_vec3.h"

namespace dembridge::springs {

// State codes, HISTORY 'SS' (spec §4.3); a code >= 0 is the TSERIES id of an UNSPRING unload curve (Q7).
enum SpringCode : int { kRegular = -3, kManaged = -2, kZeroForce = -1 };

struct SpringState {
  double stroke = 0.0;             // s = len - stroke0 of the last step
  double stroke_comp = 0.0;        // sc, accumulated compressive stroke (§4.2)
  double stroke_tens = 0.0;        // st, accumulated tensile stroke
  double yield_comp = 0.0;         // yc: ylim[0], later the latest compression backbone force
  double yield_tens = 0.0;         // yt: ylim[1], later the latest tension backbone force
  double force_elastic = 0.0;      // SF of the last step (f_prev of the next)
  double tangent_stiffness = 0.0;  // k_tan (ratio dashpot, kskn friction, CRITICAL)
  Vec3 friction_disp{};            // delta, tangential spring displacement (kskn > 0)
  Vec3 direction{};                // z of the last step (CRITICAL of follower/planar springs)
  double length = 0.0;             // |q - p| of the last step (output LENGTH)
  double force_total = 0.0;        // F = elastic + dashpot (output F)
  double friction_force = 0.0;     // |friction| (output FF)
  bool yielded = false;
  bool unloading = false;
  int code = kRegular;

  // Fresh state of a spring with this law (yield limits = ylim; code -1 if inactive).
  static SpringState initial(const SpringLaw& law, bool inactive = false);

  static constexpr int kPackedSize = 20;  // doubles written by pack()
  // Inline: the spring fix packs and unpacks every spring every step.
  void pack(double* buf) const;
  void unpack(const double* buf);
  static SpringState unpacked(const double* buf);  // built from buf directly (no default fill first)
};

// Every field is stored as a double; ints and flags are exact in a double, so pack/unpack is lossless.
inline void SpringState::pack(double* b) const {
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

inline SpringState SpringState::unpacked(const double* b) {
  return {b[0],  b[1],  b[2],  b[3],  b[4],         b[5],         b[6],
          {b[7], b[8], b[9]},        {b[10], b[11], b[12]},      b[13],
          b[14], b[15], b[16] != 0.0, b[17] != 0.0, static_cast<int>(b[18])};
}

inline void SpringState::unpack(const double* b) { *this = unpacked(b); }

}  // namespace dembridge::springs
