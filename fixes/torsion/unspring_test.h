// The per-step UNSPRING test (spec parmec-springs §8): a pure function of the rule, its counter, the
// step number and the tspring entity values gathered (globally, across ranks) for this step.
#pragma once

#include <utility>
#include <vector>

#include "spring_state.h"
#include "unspring_rule.h"

namespace dembridge::torsion {

// Entity value of one spring after this step's force evaluation (STROKE, F, SF, FF: spec §8 step 3).
double entity_value(Entity e, const springs::SpringState& st);

// SUM (from 0), MIN (from +REAL_MAX), MAX (from -REAL_MAX) of the values in tsprings order, |value| if abs.
double combine(const UnspringRule& rule, const std::vector<double>& values);

struct UnspringOutcome {
  bool tested = false;     // step % nsteps == 0 and the rule has not fired yet
  double value = 0.0;      // combined entity value (if tested)
  bool exceeded = false;   // value < min or value > max
  int remaining = 0;       // counter after this step (starts at nfreq; 0 = fired)
  bool triggered = false;  // fired at this step
  // Spring state codes to apply after this step's evaluation (effective from the next step): every
  // mspring -> unload_code (TSERIES id >= 0, or -1), then every activate entry -> -3.
  std::vector<std::pair<int, int>> new_codes;
};

// `step` counts real time steps from the start (0 for the first force evaluation; Q14 fixed: Parmec
// counts DEM calls); the test runs when step % nsteps == 0. `values` holds entity_value of each tspring,
// in tsprings order. `remaining` is the rule's counter before this step (nfreq initially).
UnspringOutcome unspring_test(const UnspringRule& rule, int remaining, long step, const std::vector<double>& values);

}  // namespace dembridge::torsion
