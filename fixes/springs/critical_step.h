// CRITICAL: stable time step estimates per spring and per particle (spec parmec-springs §13,
// quirks Q17, Q18 and Q21 fixed).
#pragma once

#include <array>

#include "spring_law.h"
#include "spring_vec3.h"

namespace dembridge::springs {

struct CriticalEstimate {
  double step;   // h = (2/omega)(sqrt(1 + xi^2) - xi)
  double omega;  // natural frequency
  double xi;     // damping ratio
};

// h of a damped oscillator; 1.0 if omega == 0 (as Parmec).
CriticalEstimate oscillator_step(double omega, double xi);

// Per spring: k_s = max |slope| of the spring table, m_s = EQM of the spring's points along its current
// direction; xi = the ratio, or max |dashpot slope| / (2 m_s omega).
// parmec_order: Parmec's rounding (critical_parmec_order.h).
CriticalEstimate spring_critical(const SpringLaw& law, double m_s, bool parmec_order = false);

// Largest damping coefficient of a spring, as the per-particle estimate uses it:
// ratio: zeta 2 sqrt(k_s m_s); table: max |dashpot slope|; none: 0.
double spring_max_damping(const SpringLaw& law, double m_s);

// Per particle: accumulate every spring attached to the particle (each spring with its own dashpot and
// planar flag: Q18 fixed), then estimate.
class ParticleCritical {
 public:
  // parmec_order: accumulate and estimate in the operation order of Parmec's kernels
  // (critical_parmec_order.h); add the springs in Parmec's spring order for its rounding of the sums.
  explicit ParticleCritical(bool parmec_order = false) : parmec_(parmec_order) {}
  // k_s, e: spring_critical's stiffness and spring_max_damping(); d: the spring's current direction
  // (0 = unknown: counts 1 per axis); planar: d is the plane normal of a PLANAR spring; arm: body-frame
  // arm Λ^T (p - x) of the spring point on this particle.
  void add_spring(double k_s, double e, const Vec3& d, bool planar, const Vec3& arm);
  bool empty() const { return count_ == 0; }
  // Smaller of the translational and rotational estimates; REAL_MAX step without springs; the
  // rotational one is skipped when the rotational stiffness is zero (Q21 fixed: Parmec returns NaN).
  // inertia: referential J, row-major.
  CriticalEstimate estimate(double mass, const std::array<double, 9>& inertia) const;

 private:
  int count_ = 0;
  Vec3 axis_count_{};
  double k_max_ = 0.0;
  double e_max_ = 0.0;
  std::array<double, 9> arm_sum_{};  // sum of |A|^2 I - A A^T
  bool parmec_ = false;
  std::array<double, 6> krot_{};     // parmec_: the same sums as Parmec keeps them (K11 K22 K33 K21 K31 K32)
};

}  // namespace dembridge::springs
