// Builds the oracle torsion cases (torsion_spring_one, analytic_torsion) from their meta.json and
// replays them with RigidReplay, measuring the worst deviations against a history.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "deviation.h"
#include "oracle_data.h"
#include "rigid_replay.h"
#include "spring_table.h"

struct TorsionDeviations {
  Deviation angle;   // ROLL, PITCH, YAW
  Deviation omega;   // OX, OY, OZ (ω_{n+1} in row n)
  Deviation torque;  // TRQTOT_*, TRQSPR_*, TX..TZ
  double worst() const;
  void print(const std::string& name) const;
};

// A case: one body tied to space by one torsion spring, Λ0 = I, initial spin ω0.
struct TorsionCase {
  double h = 1e-3;
  double inertia = 1.0;  // isotropic J
  replay::V3 omega0 = replay::V3::Zero();
  replay::Torsion spring;
  // tables referenced by spring.law, on the heap so that copies of the case stay valid
  std::vector<std::shared_ptr<const dembridge::springs::SpringTable>> tables;
  const dembridge::springs::SpringTable* keep(dembridge::springs::SpringTable t) {
    tables.push_back(std::make_shared<const dembridge::springs::SpringTable>(std::move(t)));
    return tables.back().get();
  }
};

// torsion_spring_one case NN (meta_caseNN.json, cube J = 1000/6) under `root` (oracle or fixedQ1Q3 dir).
TorsionCase torsion_spring_one_case(const std::string& root, int number, std::string& file);
// analytic_torsion case by name (I = 2, k = 50, tables on all three axes, zdir z, xdir x).
TorsionCase analytic_torsion_case(const std::string& root, const std::string& name, std::string& file);

// Replays `c` with quirks on/off; rows aligned by step number (row n = step n, spec §1.3).
TorsionDeviations replay_case(const TorsionCase& c, const oracle::History& h, bool q1, bool q3,
                              bool parmec_axis_inertia = false);
