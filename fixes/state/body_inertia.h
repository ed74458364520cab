// The referential inertia tensor of a Parmec body (one atom), written once for fix parmec/spring,
// parmec/torsion and parmec/rigid: from a per-atom property d2_NAME with 6 columns (Parmec's list
// Ixx Iyy Izz Ixy Ixz Iyz, the fixes' `inertia NAME` keyword), else the sphere's 0.4 m r^2.
#pragma once

#include "pointers.h"

#include <array>
#include <string>

namespace dembridge::state {

class BodyInertia : protected LAMMPS_NS::Pointers {
 public:
  using Tensor = std::array<double, 9>;  // row-major
  // cmd: "fix ID style", the prefix of the ERROR for a missing or malformed property
  BodyInertia(LAMMPS_NS::LAMMPS *lmp, std::string cmd) : Pointers(lmp), cmd_(std::move(cmd)) {}
  void set_name(const std::string &name) { name_ = name; }  // empty: the sphere's inertia
  const std::string &name() const { return name_; }

  // The property's per-atom rows (local and ghost), looked up at each use because Atom::sort and exchange
  // reallocate them; nullptr without a name. ERROR naming the fix if it is not a d2_ property of 6 columns.
  double **rows() const;
  // J of atom i (math/inertia.h; mass: its mass; the sphere's needs radius, else 0).
  Tensor tensor(int i, double mass) const;
  // J⁻¹ of atom i (math::inverse_inertia): 1/J on a diagonal tensor, else Parmec's cofactor inverse (its
  // INVERT, as Parmec's DEM call inverts it); zero where J is zero (an atom without inertia).
  Tensor inverse(int i, double mass) const;

 private:
  std::string cmd_, name_;
};

}  // namespace dembridge::state
