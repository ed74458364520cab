// Elastic spring force and the unload + ylim state machine (spec parmec-springs §4).
#pragma once

#include "SpringLaw.h"
#include "SpringState.h"

namespace dembridge::springs {

// One step of a regular or UNSPRING-managed spring (codes -3/-2): updates st.stroke, the yield
// state and st.tangent_stiffness and returns the elastic force F. stroke = len - stroke0 of this
// step, offset = o(t_n) (0 without an offset TSERIES; ignored once yielded, §4.2).
double elastic_step(const SpringLaw& law, SpringState& st, double stroke, double offset);

// One step of a spring being unloaded by UNSPRING along `curve` (code >= 0, spec §4.3): any motion
// reduces |F|; when the force would change sign it becomes 0 and the code becomes kZeroForce.
double unspring_unload_step(const SpringTable& curve, SpringState& st, double stroke);

}  // namespace dembridge::springs
