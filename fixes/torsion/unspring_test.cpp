#include "unspring_test.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace dembridge::torsion {

double entity_value(Entity e, const springs::SpringState& st) {
  switch (e) {
    case Entity::Stroke: return st.stroke;
    case Entity::F: return st.force_total;
    case Entity::FF: return st.friction_force;
    default: return st.force_elastic;
  }
}

double combine(const UnspringRule& r, const std::vector<double>& values) {
  constexpr double kMax = std::numeric_limits<double>::max();  // Parmec's REAL_MAX start values
  double acc = r.op == Operator::Sum ? 0.0 : (r.op == Operator::Min ? kMax : -kMax);
  for (double v : values) {
    const double x = r.abs ? std::fabs(v) : v;
    if (r.op == Operator::Sum)
      acc += x;
    else if (r.op == Operator::Min)
      acc = x < acc ? x : acc;
    else
      acc = x > acc ? x : acc;
  }
  return acc;
}

UnspringOutcome unspring_test(const UnspringRule& r, int remaining, long step, const std::vector<double>& values) {
  UnspringOutcome out;
  out.remaining = remaining;
  if (remaining <= 0 || step % r.nsteps != 0) return out;
  if (values.size() != r.tsprings.size())
    throw std::invalid_argument("UNSPRING: expected one entity value per tspring");
  out.tested = true;
  out.value = combine(r, values);
  out.exceeded = out.value < r.min || out.value > r.max;
  if (!out.exceeded) return out;
  out.remaining = remaining - 1;  // failures are counted cumulatively, not necessarily consecutively
  if (out.remaining > 0) return out;
  out.triggered = true;
  for (int s : r.msprings) out.new_codes.emplace_back(s, r.unload_code(s));
  for (int s : r.activate) out.new_codes.emplace_back(s, springs::kRegular);  // Q15: at the trigger
  return out;
}

}  // namespace dembridge::torsion
