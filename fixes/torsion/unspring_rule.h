// UNSPRING rule: parameters, input validation and the input effects on spring state codes
// (spec parmec-springs §8, §4.3, quirks Q7, Q13, Q14, Q15).
#pragma once

#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "time_series.h"

namespace dembridge::torsion {

enum class Entity { Stroke, F, SF, FF };  // STROKE s, F = F_total, SF = elastic F, FF = |friction|
enum class Operator { Sum, Min, Max };

Entity parse_entity(const std::string& name);      // throws std::invalid_argument for other names
Operator parse_operator(const std::string& name);  // SUM | MIN | MAX

struct UnspringRule {
  std::vector<int> tsprings;  // springs whose entity is tested (non-empty, unique)
  std::vector<int> msprings;  // springs modified at the trigger (non-empty, unique)
  double min = -std::numeric_limits<double>::infinity();  // limits; None = unbounded
  double max = std::numeric_limits<double>::infinity();
  Entity entity = Entity::SF;
  Operator op = Operator::Sum;
  bool abs = false;
  long nsteps = 1;  // test every nsteps real time steps (Q14 fixed)
  int nfreq = 1;    // number of (cumulative) failed tests that fires the rule; it fires once
  std::optional<int> unload;         // TSERIES id of one unload curve for all msprings (Parmec's form)
  std::map<int, int> unload_by_spring;  // Q13: spring id -> TSERIES id (the manual's dict); overrides `unload`
  std::vector<int> activate;         // inactive springs switched on (-1 -> -3) at the trigger (Q15: immediately)

  // State code a mspring takes at the trigger: the TSERIES id of its unload curve (Q7: the TSERIES
  // number itself is reported), or -1 (instantaneous removal, the default).
  int unload_code(int spring) const;

  // Intrinsic checks; messages start with "UNSPRING #index": empty or repeated tsprings/msprings/
  // activate entries, min >= max, NaN limits, nsteps < 1, nfreq < 1, a negative TSERIES id, a per-spring
  // unload key that is not in msprings.
  void validate(int index) const;
};

// Input effects of rules given in input order (spec §8), on `codes` (spring id -> state code, all known
// springs; -3 regular, -1 created inactive): every mspring becomes -2 and must be known and neither -2
// (managed by an earlier rule) nor -1; every activate entry must be known and inactive (-1).
// Throws std::invalid_argument naming the rule.
void register_rule(const UnspringRule& rule, int index, std::map<int, int>& codes);

// Unload curves must exist, be proper TSERIES (>= 2 points) and strictly increasing (spec §8).
// `find` returns the TSERIES of an id, or null if there is none.
void check_unload_curves(const UnspringRule& rule, int index,
                         const std::function<const springs::TimeSeries*(int)>& find);

}  // namespace dembridge::torsion
