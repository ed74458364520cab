// Is a 3x3 matrix from MBDyn a rotation? MBDyn's orientation matrices are orthonormal to
// round-off (1e-15); a zero, scaled, skewed or mirrored matrix means a broken peer, and would move
// a rigid group's atoms off their body (and out of the box) without a word. LAMMPS-free.
#pragma once

#include <array>
#include <string>

namespace dembridge::mbdyn {

// Largest |(R^T R - I)_ij| accepted. Far above round-off of a real rotation (1e-15 .. 1e-12 after
// a few products), far below any defect worth a run (a 1e-6 shear moves a 1 m body by 1 um).
constexpr double kRotationTolerance = 1e-6;

// Empty when R (row-major) is a proper rotation within tol; otherwise what is wrong with it, for
// an error message ("is all zero", "is not orthonormal: max |R^T R - I| = ...", "has
// determinant -1: a reflection").
std::string rotation_matrix_defect(const std::array<double, 9>& R, double tol = kRotationTolerance);

}  // namespace dembridge::mbdyn
