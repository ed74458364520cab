// Tangential friction of a spring (spec parmec-springs §6).
#pragma once

#include "spring_state.h"
#include "spring_vec3.h"

namespace dembridge::springs {

// Friction force on part1 for one step. u_t: tangential relative velocity of point2 w.r.t. point1;
// force_total: F (limit mu |F|); force_elastic: SF (F == 0 resets delta, switches off the dashpot
// part); damping: dashpot coefficient c of this step; dt: step. Updates st.friction_disp (kskn > 0)
// and st.friction_force.
Vec3 friction_step(double mu, double kskn, SpringState& st, const Vec3& u_t, double force_total, double force_elastic,
                   double damping, double dt);

}  // namespace dembridge::springs
