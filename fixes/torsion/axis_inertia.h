// Inertias about the torsion axes used by critical-ratio dampers (spec parmec-springs §7).
#pragma once

#include "torsion_frame.h"

namespace dembridge::torsion {

// Spatial inverse inertia Λ J⁻¹ Λᵀ of a body from its rotation and body-frame inverse inertia
// (both row-major).
Mat3 spatial_inverse_inertia(const Mat3& rotation, const Mat3& body_inverse_inertia);

// (I_xx, I_yy, I_zz) = diagonal of M⁻¹, M = Rᵀ (W1 + W2) R, R = [x y z] the current frame, W_i the
// spatial inverse inertias (W2 omitted for part2 = -1). This is the corrected form of spec §7: Parmec
// builds R (J1⁻¹ + J2⁻¹) Rᵀ from referential inverse inertias, which mixes frames for anisotropic
// bodies; both agree for isotropic inertia (all oracle cases).
Vec3 axis_inertias(const TorsionFrame& frame, const Mat3& spatial_inv_inertia1, const Mat3* spatial_inv_inertia2);

// Parmec's formula (spec §7): diagonal of (R (J1⁻¹ + J2⁻¹) Rᵀ)⁻¹ with the referential inverse inertias.
// Equal to axis_inertias for isotropic bodies while Λ is orthogonal; with Q3 (Λ drifting from
// orthogonality) the two differ at 1e-7, so 'order parmec' uses this one.
Vec3 axis_inertias_parmec(const TorsionFrame& frame, const Mat3& body_inv_inertia1, const Mat3* body_inv_inertia2);

}  // namespace dembridge::torsion
