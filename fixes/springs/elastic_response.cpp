#include "elastic_response.h"

#include <cmath>

namespace dembridge::springs {

namespace {

// Continue the backbone of the direction of ds from its accumulated stroke (sc or st) and record the
// new latest backbone force as the limit of that side.
double load_backbone(const SpringLaw& law, SpringState& st, double ds) {
  if (ds < 0.0) {
    st.stroke_comp += ds;
    const auto r = law.spring->lookup(st.stroke_comp, law.fused);
    st.tangent_stiffness = r.slope;
    st.yield_comp = r.value;
    return r.value;
  }
  st.stroke_tens += ds;
  const auto r = law.spring->lookup(st.stroke_tens, law.fused);
  st.tangent_stiffness = r.slope;
  st.yield_tens = r.value;
  return r.value;
}

}  // namespace

double yielded_step(const SpringLaw& law, SpringState& st, double stroke) {
  const double ds = stroke - st.stroke;
  const double f0 = st.force_elastic;
  st.stroke = stroke;
  const SpringTable& unload = *law.unload;
  if (f0 * ds > 0.0) {  // moving away from zero force
    if (!st.unloading) return load_backbone(law, st, ds);
    // re-loading along the unload curve; tangent = unload slope (Q6 fixed: Parmec keeps a stale value)
    const double slope = unload.lookup_by_force(f0).slope;
    const double f = f0 + slope * ds;
    st.tangent_stiffness = slope;
    if (!beyond_limits(st, f)) return f;
    st.unloading = false;
    return load_backbone(law, st, ds);
  }
  // moving towards zero force (also ds == 0 or f0 == 0): unload curve shifted through (s, f0)
  const auto inv = unload.lookup_by_force(f0);
  st.tangent_stiffness = inv.slope;
  double f = f0 + inv.slope * ds;
  if (f * f0 < 0.0) {  // crossed zero: exact value on the shifted curve
    const auto r = unload.lookup(inv.at + ds);
    f = r.value;
    st.tangent_stiffness = r.slope;
  }
  if (beyond_limits(st, f)) {
    st.unloading = false;
    return load_backbone(law, st, ds);
  }
  st.unloading = true;
  return f;
}

void first_yield(SpringState& st, double stroke, double f) {
  st.yielded = true;
  if (f < 0.0) {
    st.stroke_comp = stroke;
    st.stroke_tens = 0.0;
    st.yield_tens = 0.0;
  } else {
    st.stroke_comp = 0.0;
    st.stroke_tens = stroke;
    st.yield_comp = 0.0;
  }
}

double unspring_unload_step(const SpringTable& curve, SpringState& st, double stroke) {
  const double ds = stroke - st.stroke;
  const double f0 = st.force_elastic;
  st.stroke = stroke;
  const double slope = curve.lookup_by_force(f0).slope;
  st.tangent_stiffness = slope;
  const double sgn = f0 > 0.0 ? 1.0 : -1.0;
  double f = f0 - sgn * std::fabs(slope * ds);
  if (f * f0 < 0.0) {
    f = 0.0;
    st.code = kZeroForce;
  }
  return f;
}

}  // namespace dembridge::springs
