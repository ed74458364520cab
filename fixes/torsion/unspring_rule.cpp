#include "unspring_rule.h"

#include <cmath>
#include <set>
#include <stdexcept>

namespace dembridge::torsion {

namespace {

[[noreturn]] void fail(int index, const std::string& what) {
  throw std::invalid_argument("UNSPRING #" + std::to_string(index) + ": " + what);
}

void unique_nonempty(const std::vector<int>& ids, const char* name, int index, bool may_be_empty) {
  if (ids.empty() && !may_be_empty) fail(index, std::string(name) + " must be non-empty");
  std::set<int> seen;
  for (int id : ids)
    if (!seen.insert(id).second) fail(index, "spring " + std::to_string(id) + " listed twice in " + name);
}

}  // namespace

Entity parse_entity(const std::string& n) {
  if (n == "STROKE") return Entity::Stroke;
  if (n == "F") return Entity::F;
  if (n == "SF") return Entity::SF;
  if (n == "FF") return Entity::FF;
  throw std::invalid_argument("UNSPRING: unknown entity '" + n + "' (expected STROKE, F, SF or FF)");
}

Operator parse_operator(const std::string& n) {
  if (n == "SUM") return Operator::Sum;
  if (n == "MIN") return Operator::Min;
  if (n == "MAX") return Operator::Max;
  throw std::invalid_argument("UNSPRING: unknown operator '" + n + "' (expected SUM, MIN or MAX)");
}

int UnspringRule::unload_code(int spring) const {
  const auto it = unload_by_spring.find(spring);
  if (it != unload_by_spring.end()) return it->second;
  return unload ? *unload : -1;
}

void UnspringRule::validate(int index) const {
  unique_nonempty(tsprings, "tsprings", index, false);
  unique_nonempty(msprings, "msprings", index, false);
  unique_nonempty(activate, "activate", index, true);
  if (std::isnan(min) || std::isnan(max)) fail(index, "limits must not be NaN (use None for no limit)");
  if (!(min < max)) fail(index, "limits must satisfy min < max, got (" + std::to_string(min) + ", " + std::to_string(max) + ")");
  if (nsteps < 1) fail(index, "nsteps must be >= 1");
  if (nfreq < 1) fail(index, "nfreq must be >= 1");
  if (unload && *unload < 0) fail(index, "unload TSERIES id must be >= 0");
  const std::set<int> m(msprings.begin(), msprings.end());
  for (const auto& [spring, ts] : unload_by_spring) {
    if (!m.count(spring)) fail(index, "unload curve given for spring " + std::to_string(spring) + ", which is not in msprings");
    if (ts < 0) fail(index, "unload TSERIES id of spring " + std::to_string(spring) + " must be >= 0");
  }
}

void register_rule(const UnspringRule& r, int index, std::map<int, int>& codes) {
  for (int s : r.tsprings)
    if (!codes.count(s)) fail(index, "unknown spring " + std::to_string(s) + " in tsprings");
  for (int s : r.msprings) {
    const auto it = codes.find(s);
    if (it == codes.end()) fail(index, "unknown spring " + std::to_string(s) + " in msprings");
    if (it->second == -2) fail(index, "spring " + std::to_string(s) + " in msprings is already managed by another UNSPRING");
    if (it->second == -1) fail(index, "spring " + std::to_string(s) + " in msprings is inactive");
  }
  for (int s : r.activate) {
    const auto it = codes.find(s);
    if (it == codes.end()) fail(index, "unknown spring " + std::to_string(s) + " in activate");
    if (it->second != -1) fail(index, "spring " + std::to_string(s) + " in activate is already active (create it inactive)");
  }
  for (int s : r.msprings) codes[s] = -2;
}

void check_unload_curves(const UnspringRule& r, int index, const std::function<const springs::TimeSeries*(int)>& find) {
  std::set<int> ids;
  if (r.unload) ids.insert(*r.unload);
  for (const auto& kv : r.unload_by_spring) ids.insert(kv.second);
  for (int id : ids) {
    const springs::TimeSeries* ts = find(id);
    if (!ts) fail(index, "unknown unload TSERIES " + std::to_string(id));
    if (ts->is_constant()) fail(index, "unload TSERIES " + std::to_string(id) + " must have at least two points");
    if (!ts->as_table("unload").strictly_increasing_values())
      fail(index, "unload TSERIES " + std::to_string(id) + " must be strictly increasing");
  }
}

}  // namespace dembridge::torsion
