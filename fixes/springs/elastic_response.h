// Elastic spring force and the unload + ylim state machine (spec parmec-springs §4).
#pragma once

#include "spring_law.h"
#include "spring_state.h"

namespace dembridge::springs {

// One step of a regular or UNSPRING-managed spring (codes -3/-2): updates st.stroke, the yield
// state and st.tangent_stiffness and returns the elastic force F. stroke = len - stroke0 of this
// step, offset = o(t_n) (0 without an offset TSERIES; ignored once yielded, §4.2).
// Inline (below): every spring calls it every step; the yield paths stay out of line.
[[gnu::always_inline]] inline double elastic_step(const SpringLaw& law, SpringState& st, double stroke, double offset);

// Whether f lies outside the current yield limits [yc, yt].
inline bool beyond_limits(const SpringState& st, double f) { return f < st.yield_comp || f > st.yield_tens; }
// The step of a spring that has yielded (unload + ylim, spec §4.2).
double yielded_step(const SpringLaw& law, SpringState& st, double stroke);
// The first yield at this step's stroke s and backbone force f: sc/st start from s (without offset).
void first_yield(SpringState& st, double stroke, double f);

// One step of a spring being unloaded by UNSPRING along `curve` (code >= 0, spec §4.3): any motion
// reduces |F|; when the force would change sign it becomes 0 and the code becomes kZeroForce.
double unspring_unload_step(const SpringTable& curve, SpringState& st, double stroke);

[[gnu::always_inline]] inline double elastic_step(const SpringLaw& law, SpringState& st, double stroke, double offset) {
  if (law.general() && st.yielded) return yielded_step(law, st, stroke);
  st.stroke = stroke;
  const auto r = law.spring->lookup(stroke - offset, law.fused);
  st.tangent_stiffness = r.slope;
  // first yield: this step still returns the backbone value
  if (law.general() && beyond_limits(st, r.value)) first_yield(st, stroke, r.value);
  return r.value;
}

}  // namespace dembridge::springs
