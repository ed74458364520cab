// One force evaluation of one spring: state code dispatch, elastic law, dashpot, friction
// (spec parmec-springs §4.3, §5, §6). Advances the spring state: call exactly once per time step.
#pragma once

#include "elastic_response.h"
#include "spring_friction.h"
#include "spring_geometry.h"
#include "spring_law.h"
#include "spring_state.h"
#include "spring_vec3.h"

#include <cmath>

namespace dembridge::springs {

struct SpringStepInput {
  double stroke0 = 0.0;            // reference_stroke0() of the spring
  double time = 0.0;               // t_n, argument of the offset curve
  double dt = 0.0;                 // step (kskn friction)
  double equivalent_mass = 0.0;    // EQM along frame.z; read only if law.needs_equivalent_mass()
  const SpringTable* unspring_unload = nullptr;  // the unload curve of code >= 0 (UNSPRING), else unused
};

struct SpringForce {
  double total = 0.0;    // F = elastic + dashpot (output F)
  double elastic = 0.0;  // SF
  double damping = 0.0;  // dashpot coefficient c used this step
  Vec3 friction{};       // friction force on part1
  Vec3 on_part1{};       // z F + friction: apply at p to part1 and the opposite at q to part2
};

// Inline (below): the spring fix calls it for every spring every step.
[[gnu::always_inline]] inline SpringForce advance_spring(const SpringLaw& law, SpringState& st, const SpringFrame& frame,
                                                          const SpringStepInput& in);

namespace detail {

// Dashpot force and coefficient c (spec §5): table slope, or c = zeta 2 sqrt(|k_tan| m_eq).
[[gnu::always_inline]] inline void dashpot(const SpringLaw& law, const SpringState& st, double velocity, double m_eq, double& force, double& c) {
  if (law.ratio_dashpot()) {
    c = law.damping_ratio * 2.0 * std::sqrt(std::fabs(st.tangent_stiffness) * m_eq);
    force = c * velocity;
  } else if (law.dashpot) {
    const auto r = law.dashpot->lookup(velocity, law.fused);
    force = r.value;
    c = r.slope;
  } else {
    force = 0.0;
    c = 0.0;
  }
}

}  // namespace detail

[[gnu::always_inline]] inline SpringForce advance_spring(const SpringLaw& law, SpringState& st, const SpringFrame& frame,
                                                          const SpringStepInput& in) {
  SpringForce out;
  const double stroke = frame.len - in.stroke0;
  if (st.code <= kManaged) {
    const double offset = law.offset ? law.offset->lookup(in.time, law.fused).value : 0.0;
    out.elastic = elastic_step(law, st, stroke, offset);
    double fd = 0.0;
    detail::dashpot(law, st, frame.velocity, in.equivalent_mass, fd, out.damping);
    // the dashpot is off whenever the elastic force is exactly zero (gaps, dead bands)
    out.total = out.elastic + (out.elastic == 0.0 ? 0.0 : fd);
  } else if (st.code == kZeroForce) {  // inactive or removed: stroke still tracked
    st.stroke = stroke;
    st.tangent_stiffness = 0.0;
  } else if (!in.unspring_unload) {  // no curve given: instantaneous removal (UNSPRING default)
    st.stroke = stroke;
    st.tangent_stiffness = 0.0;
    st.code = kZeroForce;
  } else {  // being unloaded by UNSPRING: no dashpot
    out.elastic = unspring_unload_step(*in.unspring_unload, st, stroke);
    out.total = out.elastic;
  }
  st.force_elastic = out.elastic;
  if (law.friction > 0.0)
    out.friction = friction_step(law.friction, law.kskn, st, frame.u_tangential, out.total, out.elastic, out.damping, in.dt);
  st.direction = frame.z;
  st.length = frame.distance;
  st.force_total = out.total;
  out.on_part1 = out.total * frame.z + out.friction;
  return out;
}

}  // namespace dembridge::springs
