// Per-type-pair coefficients, derived once per init() from fix property/global (materials/)
// or from the LAMMPS numeric pair_style arguments. Only the fields a model needs are set.
#pragma once

namespace dembridge::gran {

// R: double, or Lanes4 (four pairs' coefficients, lane_math.h)
template <class R> struct PairCoeffsT {
  // material models (spec granular-models §4)
  R Yeff{}, Geff{};  // effective Young's and shear modulus
  R lnE{}, beta{};   // log of restitution, damping factor ln e / sqrt(ln²e + π²)
  R char_vel{};        // hooke: characteristicVelocity
  // stiffness models (§5.3/5.4) and the LAMMPS numeric dialect
  R kn{}, kt{}, gamman{}, gammat{};
  // tangential
  R mu{};  // coefficientFriction
  // rolling, cohesion, viscous (issue: rolling/cohesion)
  R mu_roll{}, eta_roll{}, roll_stiffness{};
  R cohesion_energy_density{};
  R fluid_viscosity{}, critical_stokes{}, ln_max_restitution{};
};
using PairCoeffs = PairCoeffsT<double>;

}  // namespace dembridge::gran
