#include "spring_friction.h"

#include <cmath>

namespace dembridge::springs {

Vec3 friction_step(double mu, double kskn, SpringState& st, const Vec3& u_t, double force_total, double force_elastic,
                   double damping, double dt) {
  const double limit = mu * std::fabs(force_total);
  Vec3 f{};
  if (kskn == 0.0) {  // pure sliding: opposes the tangential motion, no stick state
    const double ul = norm(u_t);
    if (ul > 0.0) f = {limit * u_t[0] / ul, limit * u_t[1] / ul, limit * u_t[2] / ul};
  } else {  // stick-slip: tangential spring kskn |k_tan| and dashpot kskn |c|
    if (force_elastic == 0.0) st.friction_disp = Vec3{};
    const Vec3 trial = st.friction_disp + dt * u_t;
    const double c0 = kskn * std::fabs(st.tangent_stiffness);
    const double c1 = force_elastic == 0.0 ? 0.0 : kskn * std::fabs(damping);
    f = c0 * trial + c1 * u_t;
    const double fl = norm(f);
    if (fl > limit) {
      f = (limit / fl) * f;
      // slip: shrink delta so that c0 |delta| = limit; Q9 guard: with c0 = 0 keep the old delta
      const double tl = norm(trial);
      if (c0 > 0.0 && tl > 0.0) st.friction_disp = (limit / (c0 * tl)) * trial;
    } else {
      st.friction_disp = trial;
    }
  }
  st.friction_force = norm(f);
  return f;
}

}  // namespace dembridge::springs
