// A small LAMMPS-free rigid-body driver for the torsion kernels: Parmec's staggered leap-frog with the
// body-frame rotational update (spec parmec-springs §1.1-§1.2), written from the spec for the oracle
// comparisons. Quirks Q1 (first force evaluation sees ω h/2) and Q3 (expmap Ω2·Ω3 typo) can be switched
// on to reproduce the upstream oracle; the fixedQ1Q3 oracle is matched with both off.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "torsion_frame.h"
#include "torsion_law.h"
#include "torsion_state.h"
#include "torsion_step.h"

namespace replay {

using Mat3 = Eigen::Matrix3d;
using V3 = Eigen::Vector3d;

struct Body {
  Mat3 J = Mat3::Identity();  // referential inertia (Λ0 = I)
  Mat3 L = Mat3::Identity();  // rotation Λ (half-step values during the run)
  V3 W = V3::Zero();          // body angular velocity Ω
  V3 w = V3::Zero();          // spatial angular velocity ω
  V3 t = V3::Zero();          // spatial torque of the last step
};

struct Torsion {
  int part1 = 0, part2 = -1;
  dembridge::torsion::TorsionFrame reference;
  dembridge::torsion::TorsionLaw law;
  dembridge::torsion::TorsionState state;
  dembridge::torsion::TorsionTorque last;
};

class RigidReplay {
 public:
  RigidReplay(std::vector<Body> bodies, std::vector<Torsion> springs, double h, bool q1, bool q3);
  // Parmec's axis inertias diag(inv(R (J1⁻¹ + J2⁻¹) Rᵀ)) with referential J⁻¹ instead of the corrected
  // kernel formula (spec §7). Identical for isotropic bodies with an orthogonal Λ; differs when Λ has
  // drifted from orthogonality (Q3 emulated), which the upstream case 10 shows.
  void use_parmec_axis_inertia(bool on) { parmec_inertia_ = on; }
  void step();  // step n: torsion at Λ_{n+1/2}, ω_n, then the rotational kick/drift
  const std::vector<Body>& bodies() const { return bodies_; }
  const std::vector<Torsion>& springs() const { return springs_; }

 private:
  std::vector<Body> bodies_;
  std::vector<Torsion> springs_;
  double h_;
  bool q3_;
  bool parmec_inertia_ = false;
};

Mat3 expmap(const V3& theta, bool q3);
dembridge::torsion::Mat3 to_rowmajor(const Mat3& m);

}  // namespace replay
