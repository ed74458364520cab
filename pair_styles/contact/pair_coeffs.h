// Per-type-pair coefficients, derived once per init() from fix property/global (materials/)
// or from the LAMMPS numeric pair_style arguments. Only the fields a model needs are set.
#pragma once

#include <cstddef>

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

// The fields as one list, so that code moving all of them (or a subset, by a mask of
// coeff_bit) between a PairCoeffs and its four-lane form is written once (pair_gran_lanes.h).
template <class R> struct PairCoeffFields {
  using C = PairCoeffsT<R>;
  static constexpr R C::*kAll[] = {&C::Yeff,     &C::Geff,     &C::lnE,      &C::beta,           &C::char_vel,
                                   &C::kn,       &C::kt,       &C::gamman,   &C::gammat,         &C::mu,
                                   &C::mu_roll,  &C::eta_roll, &C::roll_stiffness, &C::cohesion_energy_density,
                                   &C::fluid_viscosity, &C::critical_stokes, &C::ln_max_restitution};
  static constexpr std::size_t kCount = sizeof(kAll) / sizeof(kAll[0]);
};
static_assert(PairCoeffFields<double>::kCount * sizeof(double) == sizeof(PairCoeffs), "PairCoeffFields lists every field");

// Bit of field f (a member pointer of PairCoeffs) in a mask over PairCoeffFields::kAll.
constexpr unsigned coeff_bit(double PairCoeffs::*f)
{
  for (std::size_t k = 0; k < PairCoeffFields<double>::kCount; k++)
    if (PairCoeffFields<double>::kAll[k] == f) return 1u << k;
  return 0;
}
// The mask of the given fields: coeff_mask(&PairCoeffs::kn, &PairCoeffs::mu).
template <class... F> constexpr unsigned coeff_mask(F... f) { return (0u | ... | coeff_bit(f)); }

}  // namespace dembridge::gran
