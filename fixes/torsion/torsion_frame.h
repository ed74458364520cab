// Reference and current (co-rotated) directions of a torsion spring (spec parmec-springs §7).
#pragma once

#include <array>

#include "math/rotation.h"
#include "spring_vec3.h"

namespace dembridge::torsion {

using springs::Vec3;
using Mat3 = std::array<double, 9>;  // row-major rotation matrix Λ (reference -> current)

inline Vec3 apply(const Mat3& m, const Vec3& v) { return math::mat_vec(m, v.data()); }
inline Mat3 identity() { return {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}; }

// Unit roll (x), pitch (y = z × x) and yaw (z) directions.
struct TorsionFrame {
  Vec3 x{}, y{}, z{};
};

// Reference frame from the user's zdir and xdir. Quirk Q10 fixed: both are normalised (Parmec divides
// zdir twice and never xdir) and must be orthogonal in either sign (|ẑ·x̂| <= 1e-8; Parmec only rejects
// a positive dot). Throws std::invalid_argument naming the rule (zero vector, not orthogonal).
TorsionFrame reference_frame(const Vec3& zdir, const Vec3& xdir);

// Current frame: the reference frame co-rotated with part1 only, x = Λ1 x0, y = Λ1 y0, z = Λ1 z0
// (Λ1 at t_{n+1/2}); also for part2 >= 0 (spec §7).
TorsionFrame current_frame(const TorsionFrame& reference, const Mat3& rotation1);

}  // namespace dembridge::torsion
