// EQM: the mass seen by a material point (or a pair of points) along a direction (spec parmec-springs §12).
#pragma once

#include <array>

#include "spring_vec3.h"

namespace dembridge::springs {

// Referential mass properties of one body.
struct BodyMass {
  double mass = 1.0;
  std::array<double, 9> inv_inertia{};  // J^-1 in the reference (body) frame, row-major
  Vec3 centre{};                        // reference mass centre X
  static BodyMass isotropic(double mass, double inertia, const Vec3& centre);
  // A body with the inertia tensor J given as Parmec's list [Ixx, Iyy, Izz, Ixy, Ixz, Iyz], inverted as
  // Parmec inverts it (math::inverse_parmec): the J⁻¹ of Parmec's eqm() for MESH and ANALYTICAL bodies.
  static BodyMass from_inertia_list(double mass, const double* six, const Vec3& centre);
};

// Which arm the point contributes with. Correct: A = X - P. ParmecQ8: the arm Parmec's spring force
// routine really uses for critical-ratio dashpots, A = X - (P - X) = 2X - P (quirk Q8, compatibility only).
enum class EqmArm { Correct, ParmecQ8 };

// Inverse mass matrix seen by point P of the body: I/m + [A]x^T J^-1 [A]x (row-major).
std::array<double, 9> point_inverse_mass(const BodyMass& body, const Vec3& P, EqmArm arm = EqmArm::Correct);

// m_eq = 1/(d^T M^-1 d) for d != 0 (d used as given), else 1/lambda_min(M^-1): the largest point
// mass (Q17 fixed: Parmec takes the maximum diagonal entry when M^-1 happens to be diagonal).
// M^-1 sums part1's and, if body2 is given, part2's contributions. Throws if M^-1 is not positive.
// fused: in the operation order and contraction of Parmec's eqm() ('order parmec'). parmec_eigenvalue (with
// fused, for 'critical parmec'): a zero d takes Parmec's own eigenvalue formula, Q17 included, as its CRITICAL.
double equivalent_mass(const BodyMass& body1, const Vec3& P1, const BodyMass* body2, const Vec3& P2, const Vec3& d,
                       EqmArm arm = EqmArm::Correct, bool fused = false, bool parmec_eigenvalue = false);

}  // namespace dembridge::springs
