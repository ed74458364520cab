// fix parmec/spring: the general spring loop (every mode, arms, spatial anchors, trial and setup evaluations,
// 'order parmec'), one spring at a time.
#include "fix_parmec_spring_step.h"

#include "math/quaternion.h"

#include "atom.h"
#include "domain.h"

#include <optional>

using namespace LAMMPS_NS;
namespace sp = dembridge::springs;

namespace dembridge {

using namespace spring_fix;

using Rot = sp::BodyRotation;

// One spring (evaluation index r of the plan). Thread-safe: reads atoms and definitions, writes only its
// record, output row r, plan_[r] and results_[r]; failures are recorded, reported by evaluate().
template <bool Parmec>
int FixParmecSpring::evaluate_spring(const EvalContext &ctx, int r)
{
  const sp::Vec3 zero3{0, 0, 0};
  double **x = atom->x, **v = atom->v;
  PlanItem &item = plan_[r];
  const int i = item.i;
  double *slot = item.slot;
  const SpringDef &d = *item.def;
  const int idx = item.key;
  SpringResult &res = results_[r];
  res.i = i;
  res.k = -1;
  res.key = idx;
  res.apply = false;
  res.failure = Failure::None;
  int flags = 0;

  // current points (spec §2.2)
  sp::Vec3 xj;
  if (d.tag2 < 0) {
    double xu[3];
    domain->unmap(x[i], atom->image[i], xu);
    xj = vec(xu);
  } else {
    xj = vec(x[i]);
  }
  // attachment points (spec §2.2). 'order parmec': as Parmec forms them, p = x + Λ(P − X) with the stored Λ
  // of fix parmec/rigid, a = p − x (also b, q); otherwise the arm from the atom quaternion.
  constexpr bool parmec = Parmec;
  sp::Vec3 a, p;
  if (parmec) {
    p = xj + sp::rotate_fused(ctx.rot[i], d.arm1);
    a = p - xj;
  } else {
    a = zero(d.arm1) ? zero3 : (ctx.quat ? Rot::of(ctx.quat[i]) : Rot::identity()).apply(d.arm1);
    p = xj + a;
  }
  int k = -1;
  sp::Vec3 b = zero3, q, normal = d.nref;
  if (d.tag2 >= 0) {
    k = part2_of(ctx, item, res, flags);
    if (k < 0) return flags | kFailed;
    if (sp::norm(vec(x[k]) - vec(x[i])) > near_) flags |= kNear;
    const bool plane = d.mode == sp::DirectionMode::Plane;
    if (parmec) {
      q = vec(x[k]) + sp::rotate_fused(ctx.rot[k], d.arm2);
      b = q - vec(x[k]);
      if (plane) normal = sp::rotate_fused(ctx.rot[k], d.nref);
    } else {
      if (!zero(d.arm2) || plane) {
        const Rot Rk = ctx.quat ? Rot::of(ctx.quat[k]) : Rot::identity();
        if (!zero(d.arm2)) b = Rk.apply(d.arm2);
        if (plane) normal = Rk.apply(d.nref);
      }
      q = vec(x[k]) + b;
    }
  } else {
    q = d.arm2;
  }

  // Commit: the state advances in hot_; trial and setup evaluations work on a copy of the record's (built
  // only then: a default-constructed copy cost ~20 Ir per spring-step)
  std::optional<sp::SpringState> copy;
  if (ctx.mode != Mode::Commit) copy.emplace(sp::SpringState::unpacked(slot + 1));
  sp::SpringState &state = copy ? *copy : hot_[r];
  sp::Vec3 F = zero3;
  bool apply = true;
  double eqm = -1.0;
  const Mode mode = ctx.mode;
  if (mode == Mode::Setup && slot[kValid] != 0.0) {
    F = vec(slot + kForce);
  } else if (mode == Mode::Setup && reader_.parmec_start) {
    apply = false;
  } else {
    sp::SpringKinematics kin;
    kin.p = p;
    kin.q = q;
    kin.normal = normal;
    const sp::Vec3 wj = ctx.omega ? vec(ctx.omega[i]) : zero3;
    const sp::Vec3 vk = k >= 0 ? vec(v[k]) : zero3;
    const sp::Vec3 wk = (k >= 0 && ctx.omega) ? vec(ctx.omega[k]) : zero3;
    kin.u = parmec ? sp::relative_velocity_parmec(vec(v[i]), wj, a, k >= 0, vk, wk, b)
                   : sp::relative_velocity(vec(v[i]), wj, a, k >= 0, vk, wk, b);
    const sp::SpringFrame frame = sp::spring_frame(d.mode, d.d, kin, parmec);
    try {
      F = law_step(ctx, d, i, k, frame, state, eqm);
    } catch (std::exception &e) {
      record_failure(res, e.what());
      return flags | kFailed;
    }
    // Commit: F reaches the record's kForce from results_[r] with the state (sync_records)
  }

  if (apply) {
    // a centre attachment has no moment arm: its torque is exactly zero (+0 instead of cross()'s signed
    // zeros; the same sums, which start at +0 and never come back to -0)
    const sp::Vec3 ta = parmec ? sp::cross_fused(a, F) : d.arm1_zero ? zero3 : sp::cross(a, F);
    res.apply = true;
    res.k = k;
    for (int c = 0; c < 3; c++) {
      res.ft[c] = F[c];
      res.ft[3 + c] = ta[c];
    }
    if (k >= 0) {
      const sp::Vec3 tb = parmec ? sp::cross_fused(b, F) : d.arm2_zero ? zero3 : sp::cross(b, F);
      for (int c = 0; c < 3; c++) {
        res.ft[6 + c] = -F[c];
        res.ft[9 + c] = -tb[c];
      }
    }
  }
  if (!ctx.fill) return flags;
  return flags | output_row(ctx, r, state, eqm, k);
}

// The general loop's share of the springs rs[0..n) on this thread.
int FixParmecSpring::general_loop(const EvalContext &ctx, const int *rs, int n)
{
  // (the lambdas inlined into the loop; evaluate_spring itself is a call, as it always was)
  if (parmec_order_)
    return thread_share(rs, n, [&](int r) __attribute__((always_inline)) { return evaluate_spring<true>(ctx, r); });
  return thread_share(rs, n, [&](int r) __attribute__((always_inline)) { return evaluate_spring<false>(ctx, r); });
}

}  // namespace dembridge
