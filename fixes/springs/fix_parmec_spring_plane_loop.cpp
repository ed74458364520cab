// fix parmec/spring: the loop of the committed point-to-plane springs from part1's centre to a plane carried by
// part2, an atom (default order).
#include "fix_parmec_spring_step.h"

#include "math/quaternion.h"

#include "atom.h"

#include <cmath>

using namespace LAMMPS_NS;
namespace sp = dembridge::springs;

namespace dembridge {

using namespace spring_fix;

using Rot = sp::BodyRotation;

// The committed step of a point-to-plane spring from part1's centre to a plane carried by part2, an atom
// (plane_r_, default order): evaluate_spring's arithmetic without part1's zero arm and its branches. Equal
// bitwise: part2's matrix, arm, normal and point q, p = x_i + 0 and the frame are formed as there; part1's
// torque is the +0 written by split_plan. Without friction the relative velocity drops w_i x 0 (it changes at
// most the sign of a zero component, which reaches only the dashpot's velocity, where it is added to a non-zero
// elastic force or dropped, as in evaluate_centres); with friction it is kept, since the friction sees the sign
// of a zero tangential component.
[[gnu::always_inline]] inline int FixParmecSpring::evaluate_plane(const EvalContext &ctx, int r)
{
  PlanItem &item = plan_[r];
  SpringResult &res = results_[r];
  int flags = 0;
  const int k = part2_of(ctx, item, res, flags);
  if (k < 0) return flags | kFailed;
  const SpringDef &d = *item.def;
  double **x = atom->x, **v = atom->v;
  const int i = item.i;
  const sp::Vec3 xi = vec(x[i]), xk = vec(x[k]);
  if (sp::norm(xk - xi) > near_) flags |= kNear;
  const sp::Vec3 zero3{0, 0, 0};
  Rot own;  // the matrix formed for this spring (no per-atom matrices): read in place otherwise, not copied
  const Rot &Rk = ctx.body_rot ? ctx.body_rot[k] : (own = ctx.quat ? Rot::of(ctx.quat[k]) : Rot::identity());
  const sp::Vec3 b = d.arm2_zero ? zero3 : Rk.apply(d.arm2);
  const sp::Vec3 normal = Rk.apply(d.nref);
  const sp::Vec3 p = xi + zero3, q = xk + b;
  const sp::Vec3 vk = vec(v[k]);
  const sp::Vec3 wk = ctx.omega ? vec(ctx.omega[k]) : zero3;
  const bool friction = d.law.friction > 0.0;
  const sp::Vec3 u = friction ? sp::relative_velocity(vec(v[i]), ctx.omega ? vec(ctx.omega[i]) : zero3, zero3, true,
                                                      vk, wk, b)
                              : (vk + sp::cross(wk, b)) - vec(v[i]);
  sp::SpringFrame frame;  // spring_frame()'s Plane case (u_tangential only for the friction)
  const sp::Vec3 w = q - p;
  frame.distance = std::sqrt(sp::dot(w, w));
  frame.z = normal;
  frame.len = sp::dot(p - q, normal);
  frame.velocity = sp::dot(normal, u);
  if (friction) frame.u_tangential = u - frame.velocity * normal;
  return flags | commit_force(ctx, r, k, frame, d.arm2_zero ? nullptr : &b);
}

// The plane loop's share of plane_r_ on this thread; first, if evaluate() asked
// for them (ctx.body_rot), every atom's matrix, shared by all threads (a barrier after it).
int FixParmecSpring::plane_loop(const EvalContext &ctx)
{
  if (ctx.body_rot) {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int j = 0; j < ctx.nall; j++) atom_rot_[j] = Rot::of(ctx.quat[j]);
  }
  return thread_share(plane_r_.data(), static_cast<int>(plane_r_.size()),
                      [&](int r) __attribute__((always_inline)) { return evaluate_plane(ctx, r); });
}

}  // namespace dembridge
