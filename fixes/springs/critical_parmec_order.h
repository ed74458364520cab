// CRITICAL in the operation order of Parmec's ISPC kernels (critical_perspring, critical_perparticle,
// time_step_task and extremum_eigenvalue of parmec.ispc), for 'critical parmec': every a*b + c of its
// expressions fused as its build fuses them (spring_vec3.h), and its floating-point literals in single
// precision, as ISPC reads an unsuffixed literal: π of the eigenvalue formula is float(π). The largest
// eigenvalue of a matrix with a double eigenvalue, common for symmetric bodies, falls in the r <= -1
// branch whose angle is float(π)/3: that costs Parmec 8.4e-9 of ω there, which this reproduces.
#pragma once

#include <array>

#include "critical_step.h"
#include "spring_vec3.h"

namespace dembridge::springs::parmec_order {

// Parmec's 3x3 symmetric eigenvalue (column-major A): the largest, or with `minimum` the smallest; on a
// diagonal matrix the largest diagonal entry either way (quirk Q17, kept here).
double extremum_eigenvalue(const std::array<double, 9>& A, bool minimum);

// Parmec's INVERT of a 3x3 matrix (column-major; a symmetric J reads the same row-major), its products
// fused: the J⁻¹ its DEM call computes and its eqm() uses.
std::array<double, 9> inverse(const std::array<double, 9>& F);

// (2/ω)(sqrt(1 + ξ²) - ξ) with 1 + ξ² fused; 1.0 for ω = 0 (per spring).
CriticalEstimate oscillator_step(double omega, double xi);

// One spring point's arm A (body frame) added to the rotational stiffness sums krot = (K11, K22, K33, K21,
// K31, K32) of |A|² I - A Aᵀ, as Parmec accumulates them.
void add_arm(std::array<double, 6>& krot, const Vec3& A);

// The axis counts of a PLANAR spring with normal d: Parmec's two in-plane vectors (d x (d + (0.123, 0.346,
// 0.789)) normalised, and that x d) summed as |t1| + |t2| per axis.
Vec3 planar_counts(const Vec3& d);

// time_step_task: the smaller of the translational and rotational estimates (ω and ξ: the larger of the
// two, as Parmec reports them). J: referential inertia (symmetric); kact: axis counts; k: largest spring
// stiffness, e: largest damping; krot as add_arm. Without rotational stiffness Parmec's estimate is NaN
// (Q21); here the translational one.
CriticalEstimate particle_step(double mass, const std::array<double, 9>& J, const Vec3& kact, double k, double e,
                               const std::array<double, 6>& krot);

}  // namespace dembridge::springs::parmec_order
