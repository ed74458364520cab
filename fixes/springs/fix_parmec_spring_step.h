// fix parmec/spring: the committed step every spring loop inlines (the law in the spring's frame, the EQM of
// ratio dashpots, part2's index, the force's stores). Included only by the fix's loop files.
#pragma once

#include "fix_parmec_spring.h"
#include "fix_parmec_spring_slot.h"
#include "math/inertia.h"
#include "spring_step.h"

#include <cmath>
#include <stdexcept>

namespace dembridge {

// This thread's share of the springs rs[0..n) (orphaned 'omp for' inside evaluate()'s parallel region, no barrier),
// each through one(r); the OR of their flags. one must be always_inline (a lambda GCC otherwise calls per spring:
// +30 Ir per spring-step in the centre loop).
template <class One>
[[gnu::always_inline]] inline int thread_share(const int *rs, int n, One one)
{
  int flags = 0;
#if defined(_OPENMP)
#pragma omp for schedule(static) nowait
#endif
  for (int m = 0; m < n; m++) flags |= one(rs[m]);
  return flags;
}

// The law's step of spring d (atoms i, k) in this frame: advances state, returns the force on part1; eqm: the
// EQM when it was computed (ratio dashpot or output wanted). Throws the kernels' errors.
[[gnu::always_inline]] inline springs::Vec3 FixParmecSpring::law_step(const EvalContext &ctx, const SpringDef &d, int i, int k,
                                                                 const springs::SpringFrame &frame, springs::SpringState &state,
                                                                 double &eqm) const
{
  springs::SpringStepInput in;
  in.stroke0 = d.stroke0;
  in.time = ctx.tnow - ctx.dt;  // Parmec's label t_n of the positions x_{n+1/2} (kernel doc §5)
  in.dt = ctx.dt;
  if (ctx.fill || d.law.needs_equivalent_mass()) {
    eqm = spring_eqm(ctx, d, i, k, frame.z);
    in.equivalent_mass = std::isnan(eqm) ? 0.0 : eqm;
  }
  if (state.code >= 0) {
    auto u = unspring_unload_.find(state.code);
    in.unspring_unload = u == unspring_unload_.end() ? nullptr : u->second;
  }
  return springs::advance_spring(d.law, state, frame, in).on_part1;
}

// EQM (spec §12) of spring d along dir (zero: largest point mass) of its atoms i (part1) and k (part2, or
// -1): with their inertia tensors ('inertia NAME', Parmec's J⁻¹ as eqm() uses it), else the sphere inertia
// 0.4 m r^2. q8_arm_: Parmec's spring-force arm 2X - P (quirk Q8).
// Inline: the isotropic branch runs for every spring every step; the general one is out of line.
inline double FixParmecSpring::spring_eqm(const EvalContext &c, const SpringDef &d, int i, int k, const springs::Vec3 &dir) const
{
  if (!c.rmass && !c.mass) return NAN;  // no masses: EQM undefined (a ratio dashpot is an ERROR in init)
  auto mass_of = [&](int j) { return c.rmass ? c.rmass[j] : c.mass[c.type[j]]; };
  if (!q8_arm_ && !spring_fix::zero(dir) && !c.inertia) {
    // isotropic inertia: d^T M^-1 d = |d|^2/m + (|A|^2 |d|^2 - (A.d)^2)/J per body (the kernel's
    // equivalent_mass without the 3x3 matrices; equal to round-off)
    const double dd = springs::dot(dir, dir);
    double lambda = 0.0;
    auto add = [&](int j, const springs::Vec3 &A, bool centre) {
      const double m = mass_of(j);
      lambda += dd / m;
      if (centre) return;  // a centre point: the term below is exactly 0 (finite directions)
      const double J = c.radius ? math::sphere_moment(m, c.radius[j]) : 0.0;
      if (J > 0.0) {
        const double ad = springs::dot(A, dir);
        lambda += (springs::dot(A, A) * dd - ad * ad) / J;
      }
    };
    add(i, d.arm1, d.arm1_zero);
    if (k >= 0) add(k, d.arm2, d.arm2_zero);
    if (!(lambda > 0.0)) throw std::invalid_argument("EQM: the inverse mass matrix is not positive along the direction");
    return 1.0 / lambda;
  }
  return spring_eqm_general(c, d, i, k, dir);
}

// Part2's local/ghost index for plan item 'item': where it was last time unless its tag moved (ghosts rebuilt)
// or images may change (periodic); flags gets kMoved if it changed. -1 (res.failure set) if it is missing.
// Starts the spring's result (not applied, no failure).
[[gnu::always_inline]] inline int FixParmecSpring::part2_of(const EvalContext &ctx, PlanItem &item, SpringResult &res,
                                                            int &flags)
{
  res.apply = false;
  res.failure = Failure::None;
  int k = item.k;
  if (k < 0 || (ctx.recheck && (ctx.periodic || k >= ctx.nall || ctx.tag[k] != item.def->tag2))) {
    k = second_atom_or_missing(item.key, item.i, true);
    if (k != item.k) flags |= kMoved;
    item.k = k;
  }
  if (k < 0) res.failure = Failure::Part2Missing;
  return k;
}

// The committed law step of spring r of the own loops (evaluate_centres, evaluate_plane) in this frame: its force
// in results_[r] (F on part1, -F on part2; sync_records copies F into the record), part2's torque -(b x F) if arm2 (b) is given, else
// split_plan's -0, part1's split_plan's +0; its output row if wanted. Returns kFailed or 0.
[[gnu::always_inline]] inline int FixParmecSpring::commit_force(const EvalContext &ctx, int r, int k,
                                                                const springs::SpringFrame &frame, const springs::Vec3 *arm2)
{
  PlanItem &item = plan_[r];
  SpringResult &res = results_[r];
  springs::SpringState &state = hot_[r];
  double eqm = -1.0;
  springs::Vec3 F;
  try {
    F = law_step(ctx, *item.def, item.i, k, frame, state, eqm);
  } catch (std::exception &e) {
    record_failure(res, e.what());
    return kFailed;
  }
  res.apply = true;  // the force reaches the record's kForce with the state (sync_records), not every step
  res.k = k;
  for (int c = 0; c < 3; c++) {
    res.ft[c] = F[c];
    res.ft[6 + c] = -F[c];
  }
  if (arm2) {
    const springs::Vec3 tb = springs::cross(*arm2, F);
    for (int c = 0; c < 3; c++) res.ft[9 + c] = -tb[c];
  }
  if (!ctx.fill) return 0;
  return output_row(ctx, r, state, eqm, k);
}

}  // namespace dembridge
