// Parmec's rigid-body update (spec parmec-springs §1.1-§1.2), LAMMPS-free: the rotation-vector exponential
// and one body-frame rotational step with a full (anisotropic) referential inertia tensor.
// Quirk Q3 (Parmec's expmap uses Ω2·Ω3 where Ω1·Ω3 belongs) can be switched on to reproduce upstream runs.
#pragma once

#include "math/rotation.h"

#include <Eigen/Dense>

namespace dembridge::rigid {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

// exp([θ]×) = I + (sin|θ|/|θ|)[θ]× + ((1 − cos|θ|)/|θ|²)[θ]×², with Parmec's Taylor series for |θ|² < 0.0305.
// float_taylor: Parmec's ISPC kernel arithmetic. Quirk Q26: the series' coefficients and threshold rounded
// to single precision (an unsuffixed ISPC literal is a float), relative error 5e-9 on the |θ|² terms; and
// Q27: its build contracts multiply-adds into fused multiply-adds (the Horner steps and the diagonal
// 1 − c s, one rounding each). Dynamics and the initial half step use them, the C++ joint solver does not.
Mat3 expmap(const Vec3 &theta, bool q3_typo, bool float_taylor = false);

// Products with the sums of Parmec's C++ macros (NNMUL, NTMUL, NVMUL, TVMUL of macros.h): k = 0, 1, 2 from the
// left, unfused. Eigen's fixed-size products do not keep that order (the third row of a 3x3 product is
// a0 b0 + (a1 b1 + a2 b2)), so the C++ parts of Parmec (joints.cpp) are reproduced with these.
Mat3 macro_mul(const Mat3 &A, const Mat3 &B);    // A B
Mat3 macro_mul_t(const Mat3 &A, const Mat3 &B);  // A Bᵀ
Vec3 macro_mv(const Mat3 &A, const Vec3 &b);     // A b
Vec3 macro_tmv(const Mat3 &A, const Vec3 &b);    // Aᵀ b

// The math layer's row-major matrices (math/inertia.h: the inertia tensors) as Eigen's, and back.
Mat3 to_mat3(const math::Mat9 &m);
math::Mat9 to_mat9(const Mat3 &m);

// math::inverse_parmec (Parmec's cofactor order, shared with fix parmec/spring's EQM) on an Eigen matrix, so
// that J⁻¹ and everything integrated with it agree bitwise with Parmec's.
Mat3 parmec_inverse(const Mat3 &J);

struct RotationStep {
  Mat3 L;   // rotation Λ_{n+3/2}
  Vec3 W;   // body angular velocity Ω_{n+1}
  Vec3 w;   // spatial angular velocity ω_{n+1} = Λ_{n+3/2} Ω_{n+1}
};

// One step of Parmec's dynamics() for the rotation: body torque T = Λᵀ t,
// Ω½ = J⁻¹[exp(−h/2 Ω) J Ω + h/2 T], Ω' = Ω + h J⁻¹(T − Ω½ × J Ω½), Λ' = Λ exp(h Ω'), ω' = Λ' Ω'.
// float_taylor: in Parmec's ISPC arithmetic (Q26, Q27: every product sum as dynamics.ispc's build fuses it).
RotationStep rotation_step(const Mat3 &J, const Mat3 &Jinv, const Mat3 &L, const Vec3 &W, const Vec3 &torque,
                           double h, bool q3_typo, bool float_taylor = false);

// Orthonormal basis (Gram-Schmidt, in order, dropping dependent vectors) of up to 3 directions;
// returns the number kept (RESTRAIN, spec §10). Operation order as Parmec's RESTRAIN.
int orthonormalise(const double *dirs, int ndirs, Vec3 out[3]);

// v minus its components along the first n basis vectors, one after the other (each dot product taken
// with the already reduced vector, as Parmec's restrain kernels do).
Vec3 remove_components(const Vec3 &v, const Vec3 basis[3], int n);

}  // namespace dembridge::rigid
