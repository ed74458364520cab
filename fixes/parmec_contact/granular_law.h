// Parmec's GRANULAR contact law (spec parmec-springs §11; Parmec forces.ispc granular_force) and the
// colour-pair table that selects its parameters. LAMMPS-free; tests/unit/parmec_contact.
#pragma once

#include "mesh_vec3.h"

#include <map>
#include <utility>

namespace dembridge::parmec_contact {

using mesh::Vec3;

// One GRANULAR pairing. damper is a ratio of critical damping (e_n = damper 2 sqrt(k_n m_eff)); kskn scales
// both the tangential spring and dashpot (k_t = kskn k_n, e_t = kskn e_n). Defaults: the seed's.
struct Pairing {
  double spring = 0.0;
  double damper = 1.0;
  double mu_static = 0.0, mu_dynamic = 0.0;
  double kskn = 0.5;
  // Throws std::invalid_argument naming the argument ("spring must be >= 0, got -1").
  void validate() const;
  bool touches() const { return spring > 0.0; }  // spring 0: no force at all (no contact is kept)
};

// Pairings by unordered colour pair; (0, 0) is the default of unspecified pairs (the seed's wildcard).
// Colours are >= 0; exactly one zero colour is refused (Parmec has no "any colour" per side).
class PairingTable {
 public:
  void set(int color1, int color2, const Pairing &p);  // throws std::invalid_argument
  const Pairing &find(int color1, int color2) const;
  bool any_contact() const;  // some pairing (or the default) has spring > 0

 private:
  Pairing default_;
  std::map<std::pair<int, int>, Pairing> pairs_;
};

// One contact seen from body i: n = unit normal pointing from the other body (or obstacle) to i,
// vij = v_other - v_i at the contact point, depth > 0 while they overlap, meff = 1/(1/m_i + 1/m_j)
// (m_i against an obstacle), h the step.
struct ContactInput {
  Vec3 n, vij;
  double depth, meff, h;
};

struct ContactOutput {
  Vec3 f;          // force on body i (the other body gets -f)
  double fn;       // normal force k_n depth + e_n vn (not clamped, as in Parmec)
  double kn, en;   // stiffness and damping of this contact (time step estimates)
};

// The force law. state: the tangential displacement s of this contact (s += h v_t first, then
// F_t = k_t s + e_t v_t; beyond the static limit |F_t| > mu_s F_n the force is scaled to mu_d F_n while s
// is kept: Parmec's rule). update = false: a setup/trial pass, F_t from the stored s (no increment) and state
// unchanged.
ContactOutput granular_force(const Pairing &p, const ContactInput &c, Vec3 &state, bool update);

inline double effective_mass(double mi, double mj) { return 1.0 / (1.0 / mi + 1.0 / mj); }

// Coefficient of restitution of the linear spring-dashpot with damping ratio zeta (contact ends when the
// overlap returns to zero): exp(-pi zeta / sqrt(1 - zeta^2)), 0 for zeta >= 1.
double restitution_of_damper(double zeta);

}  // namespace dembridge::parmec_contact
