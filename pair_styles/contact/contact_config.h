// Which sub-models a contact law is composed of, and the semantics switches between the
// LIGGGHTS and LAMMPS formulations (spec granular-models §1, §11, §13).
#pragma once

namespace dembridge::gran {

enum class NormalModel { Hooke, Hertz, HookeStiffness, HertzStiffness };
enum class TangentialModel { None, NoHistory, History };
enum class RollingModel { Off, Cdt, Epsd, Epsd2, Epsd3 };
enum class CohesionModel { Off, Sjkr, Sjkr2 };

struct ContactConfig {
  NormalModel normal = NormalModel::Hooke;
  TangentialModel tangential = TangentialModel::NoHistory;
  RollingModel rolling = RollingModel::Off;
  CohesionModel cohesion = CohesionModel::Off;
  bool viscous = false;
  bool tangential_damping = true;
  bool absolute_damping = false;
  bool tangential_reduce = false;
  bool limit_force = false;
  bool torsion_torque = false;
  bool kt_to_kn_user = false;
  // LAMMPS built-in formulation (numeric dialect): lever arm R instead of R - δ/2, damping inside
  // the Coulomb check, the del-based force expressions, optional limit_damping.
  bool lammps_formulation = false;
  bool limit_damping = false;
  // LIGGGHTS 2.x expressions where 3.8 rewrote them (same maths, other rounding, spec §11):
  // hooke γn = sqrt(4 m* kn / (1 + (π/ln e)²)) and the shear projection (s·del)/rsq · del.
  bool legacy_2x_expressions = false;
  // LIGGGHTS 3.8: a separated pair's springs (shear and rolling) are cleared only on a neighbour
  // rebuild step; a contact resuming before that continues with them. 2.x and LAMMPS clear them
  // on separation (measured against 3.8: settle200_frozenfloor, gas200_periodic, bounce_bigskin).
  bool stale_springs_until_rebuild = false;

  bool rolling_needs_history() const
  {
    return rolling == RollingModel::Epsd || rolling == RollingModel::Epsd2 || rolling == RollingModel::Epsd3;
  }
  int history_size() const { return (tangential == TangentialModel::History ? 3 : 0) + (rolling_needs_history() ? 3 : 0); }
};

}  // namespace dembridge::gran
