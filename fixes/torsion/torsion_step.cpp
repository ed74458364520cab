#include "torsion_step.h"

#include <cmath>

namespace dembridge::torsion {

namespace {

struct AxisTorque {
  double spring = 0.0;
  double total = 0.0;
};

// Spring table at `angle`, damper (table at `rate`, or ratio c = −ζ 2 sqrt(|k| I)), damper off when the
// spring torque is exactly 0 (spec §7). `l` is the law whose curves are used (the leading axis in a cone).
AxisTorque axis_torque(const AxisLaw& l, double angle, double rate, double inertia) {
  AxisTorque t;
  double k = 0.0;
  if (l.spring) {
    const auto s = l.spring->lookup(angle);
    t.spring = s.value;
    k = s.slope;
  }
  double td = 0.0;
  if (l.damper) {
    td = l.damper->lookup(rate).value;
  } else if (l.ratio) {
    const double c = -*l.ratio * 2.0 * std::sqrt(std::fabs(k) * inertia);  // negative by convention (spec §7)
    td = c * rate;
  }
  t.total = t.spring + (t.spring == 0.0 ? 0.0 : td);
  return t;
}

}  // namespace

TorsionTorque advance_torsion(const TorsionLaw& law, TorsionState& st, const TorsionStepInput& in) {
  TorsionTorque out;
  const TorsionFrame& f = in.frame;
  // angles integrated explicitly with the rates at t_n, roll-x, pitch-y, yaw-z (spec §7, Q11: code pairing)
  out.rate = {springs::dot(f.x, in.relative_omega), springs::dot(f.y, in.relative_omega),
              springs::dot(f.z, in.relative_omega)};
  for (int a = 0; a < 3; ++a) st.angle[a] += in.dt * out.rate[a];

  const Cone cone = law.cone;
  for (int a = 0; a < 3; ++a) {
    if (in_cone(cone, a)) continue;
    const AxisTorque t = axis_torque(law.axis[a], st.angle[a], out.rate[a], in.axis_inertia[a]);
    out.total[a] = t.total;
    out.spring[a] = t.spring;
  }
  if (cone != Cone::None) {
    // φ = |angles in the cone|, φ̇ = Σ angle·rate / φ, curves of the leading axis, inertia sqrt(Σ I²);
    // Q12 fixed: the ratio of the leading axis (dpitch for (pitch, yaw)), not always droll.
    double phi2 = 0.0, dot = 0.0, i2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      if (!in_cone(cone, a)) continue;
      phi2 += st.angle[a] * st.angle[a];
      dot += st.angle[a] * out.rate[a];
      i2 += in.axis_inertia[a] * in.axis_inertia[a];
    }
    const double phi = std::sqrt(phi2);
    const double phidot = phi > 0.0 ? dot / phi : 0.0;
    const AxisTorque t = axis_torque(law.axis[leading_axis(cone)], phi, phidot, std::sqrt(i2));
    for (int a = 0; a < 3; ++a) {
      if (!in_cone(cone, a)) continue;
      out.total[a] = phi > 0.0 ? st.angle[a] / phi * t.total : 0.0;
      out.spring[a] = phi > 0.0 ? st.angle[a] / phi * t.spring : 0.0;
    }
  }
  for (int i = 0; i < 3; ++i)
    out.on_part1[i] = out.total[0] * f.x[i] + out.total[1] * f.y[i] + out.total[2] * f.z[i];
  st.torque_total = out.total;
  st.torque_spring = out.spring;
  st.xdir = f.x;
  st.zdir = f.z;
  return out;
}

}  // namespace dembridge::torsion
