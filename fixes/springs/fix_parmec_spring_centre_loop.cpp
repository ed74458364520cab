// fix parmec/spring: the loop of the committed point springs between two atom centres (follower, no friction,
// default order).
#include "fix_parmec_spring_step.h"

#include "atom.h"

#include <cmath>

using namespace LAMMPS_NS;
namespace sp = dembridge::springs;

namespace dembridge {

using namespace spring_fix;

// The committed step of a point spring between two atom centres (centre_r_: follower, no friction, default
// order), the bench's and most lattices' spring: evaluate_spring's arithmetic without the arm terms. Equal
// bitwise: the points are the centres + 0 (as p = x + a with a = +0), the reach check's length is the
// frame's; the relative velocity v_k - v_i differs from (v_k + w_k x 0) - (v_i + w_i x 0) at most in the sign of
// a zero component, which reaches the force only through the dashpot's velocity, where it is added to a
// non-zero elastic force or dropped (friction, which would see it, is not in this class).
[[gnu::always_inline]] inline int FixParmecSpring::evaluate_centres(const EvalContext &ctx, int r)
{
  PlanItem &item = plan_[r];
  SpringResult &res = results_[r];
  int flags = 0;
  const int k = part2_of(ctx, item, res, flags);
  if (k < 0) return flags | kFailed;
  double **x = atom->x, **v = atom->v;
  const int i = item.i;
  const double *xi = x[i], *xk = x[k];
  const sp::Vec3 w{(xk[0] + 0.0) - (xi[0] + 0.0), (xk[1] + 0.0) - (xi[1] + 0.0), (xk[2] + 0.0) - (xi[2] + 0.0)};
  sp::SpringFrame frame;
  frame.distance = std::sqrt(sp::dot(w, w));
  if (frame.distance > near_) flags |= kNear;
  frame.len = frame.distance;
  frame.z = sp::unit_of(w, frame.len, false);
  const double *vi = v[i], *vk = v[k];
  frame.velocity = sp::dot(frame.z, sp::Vec3{vk[0] - vi[0], vk[1] - vi[1], vk[2] - vi[2]});
  return flags | commit_force(ctx, r, k, frame, nullptr);
}

// The centre loop's share of centre_r_ on this thread.
int FixParmecSpring::centre_loop(const EvalContext &ctx)
{
  return thread_share(centre_r_.data(), static_cast<int>(centre_r_.size()),
                      [&](int r) __attribute__((always_inline)) { return evaluate_centres(ctx, r); });
}

}  // namespace dembridge
