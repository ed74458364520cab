// Per-type-pair coefficients, derived once per init() from fix property/global (materials/)
// or from the LAMMPS numeric pair_style arguments. Only the fields a model needs are set.
#pragma once

namespace dembridge::gran {

struct PairCoeffs {
  // material models (spec granular-models §4)
  double Yeff = 0, Geff = 0;  // effective Young's and shear modulus
  double lnE = 0, beta = 0;   // log of restitution, damping factor ln e / sqrt(ln²e + π²)
  double char_vel = 0;        // hooke: characteristicVelocity
  // stiffness models (§5.3/5.4) and the LAMMPS numeric dialect
  double kn = 0, kt = 0, gamman = 0, gammat = 0;
  // tangential
  double mu = 0;  // coefficientFriction
  // rolling, cohesion, viscous (issue: rolling/cohesion)
  double mu_roll = 0, eta_roll = 0, roll_stiffness = 0;
  double cohesion_energy_density = 0;
  double fluid_viscosity = 0, critical_stokes = 0, ln_max_restitution = 0;
};

}  // namespace dembridge::gran
