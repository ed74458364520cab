#include "SpringStep.h"

#include <cmath>

#include "ElasticResponse.h"
#include "SpringFriction.h"

namespace dembridge::springs {

namespace {

// Dashpot force and coefficient c (spec §5): table slope, or c = zeta 2 sqrt(|k_tan| m_eq).
void dashpot(const SpringLaw& law, const SpringState& st, double velocity, double m_eq, double& force, double& c) {
  if (law.ratio_dashpot()) {
    c = law.damping_ratio * 2.0 * std::sqrt(std::fabs(st.tangent_stiffness) * m_eq);
    force = c * velocity;
  } else if (law.dashpot) {
    const auto r = law.dashpot->lookup(velocity);
    force = r.value;
    c = r.slope;
  } else {
    force = 0.0;
    c = 0.0;
  }
}

}  // namespace

SpringForce advance_spring(const SpringLaw& law, SpringState& st, const SpringFrame& frame, const SpringStepInput& in) {
  SpringForce out;
  const double stroke = frame.len - in.stroke0;
  if (st.code <= kManaged) {
    const double offset = law.offset ? law.offset->lookup(in.time).value : 0.0;
    out.elastic = elastic_step(law, st, stroke, offset);
    double fd = 0.0;
    dashpot(law, st, frame.velocity, in.equivalent_mass, fd, out.damping);
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
