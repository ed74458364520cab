// fix parmec/spring: one evaluation of the springs owned here (the loops on OpenMP threads, then every atom's
// contributions in spring order), its plan, its output rows and failures.
#include "fix_parmec_spring_step.h"
#include "rank_error.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "neighbor.h"
#include "output.h"
#include "update.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

#include <algorithm>
#include <cmath>
#include <numeric>

using namespace LAMMPS_NS;
namespace sp = dembridge::springs;

namespace dembridge {

using namespace spring_fix;

// One evaluation of every spring owned here. Commit: advance the state (once per step). Trial: on a
// copy (minimisation). Setup: re-apply the force of the last committed step (so split runs and restarts
// continue bitwise); before any committed step a trial force, or none with 'start parmec'.
void FixParmecSpring::evaluate(Mode mode)
{
  const int nlocal = atom->nlocal;
  reset_sums();
  if (refresh_plan()) {
    incidence_current_ = false;
    hot_valid_ = false;
    centre_total_ = -1;
  }
  const int total = first_[nlocal];  // evaluation index r = output row r (atoms ascending, their records in order)
  if (mode != Mode::Commit) {
    sync_records();  // trial and setup evaluations read the records
  } else if (!hot_valid_) {
    hot_.resize(total);
    for (int r = 0; r < total; r++) hot_[r] = sp::SpringState::unpacked(plan_[r].slot + 1);
    hot_valid_ = true;
  }
  local_rows(total);
  if (static_cast<int>(results_.size()) < total) results_.resize(total);
  if (centre_total_ != total) split_plan(total);

  EvalContext ctx;
  ctx.mode = mode;
  ctx.dt = update->dt;
  ctx.tnow = update->atime + (update->ntimestep - update->atimestep) * ctx.dt;
  ctx.omega = atom->omega_flag ? atom->omega : nullptr;
  ctx.quat = (atom->quat_flag && atom->quat) ? atom->quat : nullptr;
  ctx.rmass = atom->rmass_flag ? atom->rmass : nullptr;
  ctx.mass = atom->mass;
  ctx.type = atom->type;
  ctx.radius = atom->radius_flag ? atom->radius : nullptr;
  ctx.inertia = inertia_.rows();
  ctx.tag = atom->tag;
  ctx.nall = nlocal + atom->nghost;
  ctx.periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  ctx.rot = rigid_ ? rigid_->array_atom : nullptr;
  // Local and ghost indices change only when the neighbour lists are rebuilt (exchange, sort, borders).
  ctx.recheck = ctx.periodic || neighbor->ncalls != plan_builds_;
  plan_builds_ = neighbor->ncalls;
  ctx.fill = output_wanted(mode);
  near_ = near_length();
  // Committed steps in the default order: the centre-to-centre point springs and the planes carried by part2
  // from part1's centre by their own loops (fix_parmec_spring_centre_loop.cpp, fix_parmec_spring_plane_loop.cpp)
  const bool split = mode == Mode::Commit && !parmec_order_ && !general_loops_;
  // More planes carried by atoms than atoms: each atom's matrix formed once (the same doubles as per spring)
  if (split && ctx.quat && static_cast<int>(plane_r_.size()) > ctx.nall) {
    if (static_cast<int>(atom_rot_.size()) < ctx.nall) atom_rot_.resize(ctx.nall);
    ctx.body_rot = atom_rot_.data();
  }

  // Phase 1, threaded: every spring from its own record and the atoms' (read-only) data; it writes its
  // record, its output row, its plan item and its result only, so the outcome does not depend on the
  // thread count. flags: kMoved (a part2 index changed), kFailed.
  [[maybe_unused]] const int nthreads = std::max(1, comm->nthreads);  // used by the OpenMP pragmas only
  int flags = 0;
#if defined(_OPENMP)
#pragma omp parallel num_threads(nthreads) if (nthreads > 1 && nlocal > 1) reduction(| : flags)
#endif
  {
#if defined(_OPENMP)
#pragma omp single nowait
    threads_used_ = std::max(threads_used_, omp_get_num_threads());
#endif
    if (split) {
      flags |= centre_loop(ctx);
      flags |= plane_loop(ctx);
      flags |= general_loop(ctx, other_r_.data(), static_cast<int>(other_r_.size()));
    } else {
      flags |= general_loop(ctx, all_r_.data(), total);
    }
  }

  if (mode == Mode::Commit) hot_dirty_ = true;
  if (flags & kNear) note_near();

  // Phase 2, serial: failures in spring order, then the contributions.
  if (flags & kFailed)
    for (int r = 0; r < total; r++)
      if (results_[r].failure != Failure::None) report_failure(results_[r]);
  double **f = atom->f;
  double **torque = atom->torque_flag ? atom->torque : nullptr;
  auto add_to_atom = [&](int i, const double *sum) {
    for (int c = 0; c < 3; c++) f[i][c] += sum[c];
    if (torque)
      for (int c = 0; c < 3; c++) torque[i][c] += sum[3 + c];
  };
  if (!sums_.ordered()) {  // hub atoms: running sums in evaluation order (see OrderedSums)
    for (int r = 0; r < total; r++) {
      const SpringResult &res = results_[r];
      if (!res.apply) continue;
      contribute(res.i, res.key, res.ft, 1.0);
      if (res.k >= 0) contribute(res.k, res.key, res.ft + 6, 1.0);
    }
    collect_sums();
    double sum[6];
    for (int i = 0; i < nlocal; i++)
      if (!sums_.empty(i)) {
        sums_.sum(i, sum);
        add_to_atom(i, sum);
      }
    return;
  }
  // Ordered: contributions to ghosts travel as entries to their owners; local atoms sum theirs straight
  // from the results, in spring order (incidence lists rebuilt only when the atoms of a spring change),
  // merged with the entries received, so the sums equal those of storing and sorting every entry.
  if (!incidence_current_ || (flags & kMoved)) {
    inc_key_.resize(total);
    inc_atom1_.resize(total);
    inc_atom2_.resize(total);
    ghost_r_.clear();
    bool all = true;
    for (int r = 0; r < total; r++) {
      const SpringResult &res = results_[r];
      inc_key_[r] = res.key;
      inc_atom1_[r] = res.apply ? res.i : -1;
      inc_atom2_[r] = (res.apply && res.k >= 0 && res.k < nlocal) ? res.k : -1;
      if (res.apply && res.k >= nlocal) ghost_r_.push_back(r);
      all = all && res.apply;
    }
    incidence_.update(nlocal, total, inc_key_.data(), inc_atom1_.data(), inc_atom2_.data());
    incidence_current_ = all;  // otherwise rebuilt next time (the springs applied may change)
    // atoms whose every contribution has a zero torque (centre attachments: +0 on part1's side, -0 on part2's)
    torque_free_.assign(nlocal, 1);
    for (int i = 0; i < nlocal; i++)
      for (const state::LocalIncidence::Term *t = incidence_.begin(i); t != incidence_.end(i); ++t)
        if (!(t->side == 0 ? defs_[t->key].arm1_zero : defs_[t->key].arm2_zero)) torque_free_[i] = 0;
  }
  for (const int r : ghost_r_) contribute(results_[r].k, results_[r].key, results_[r].ft + 6, 1.0);
  collect_sums();

#if defined(_OPENMP)
#pragma omp parallel for num_threads(nthreads) schedule(static) if (nthreads > 1 && nlocal > 1)
#endif
  for (int i = 0; i < nlocal; i++) {
    const state::LocalIncidence::Term *t0 = incidence_.begin(i), *t1 = incidence_.end(i);
    if (parmec_order_) {
      add_in_parmec_order(i, t0, t1, f[i], torque ? torque[i] : nullptr);
      continue;
    }
    if (sums_.empty(i)) {
      if (t0 == t1) continue;
      double acc[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};  // its own array: it stays in registers
      // Only forces if every torque is a signed zero: skipping them is exact, since a sum that starts at +0
      // never becomes -0 (x + y is -0 only if both are), so adding +0 or -0 leaves it as it is.
      const int width = torque_free_[i] ? 3 : 6;
      for (const state::LocalIncidence::Term *t = t0; t != t1; ++t) {
        const double *v = results_[t->r].ft + 6 * t->side;  // signs applied (part2's side stored negated)
        if (width == 3)
          for (int c = 0; c < 3; c++) acc[c] += v[c];
        else
          for (int c = 0; c < 6; c++) acc[c] += v[c];
      }
      add_to_atom(i, acc);
    } else {
      double sum[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
      state::OrderedSums::Term terms[state::OrderedSums::kMaxOrdered];
      int n = 0;
      for (const state::LocalIncidence::Term *t = t0; t != t1 && n < state::OrderedSums::kMaxOrdered; ++t) {
        const SpringResult &res = results_[t->r];
        terms[n++] = {t->key, res.ft + 6 * t->side, 1.0};
      }
      sums_.sum_with(i, terms, n, sum);
      add_to_atom(i, sum);
    }
  }
}

// The evaluation plan: evaluation index r -> (record, definition, atom) in the order of the atoms and
// their records; part2 indices are kept from the last evaluation. Rebuilt only when records moved or
// appeared (exchange, sort, restart, new states) or the atom counts changed; returns whether it was.
bool FixParmecSpring::refresh_plan()
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  if (plan_generation_ == records_.generation() && plan_nlocal_ == nlocal && plan_nall_ == nall) return false;
  sync_records();  // through the old plan: no record moved without a callback (which syncs first)
  first_.resize(nlocal + 1);
  first_[0] = 0;
  for (int i = 0; i < nlocal; i++) first_[i + 1] = first_[i] + records_.count(i);
  plan_.resize(first_[nlocal]);
  for (int i = 0; i < nlocal; i++)
    for (int s = 0, r = first_[i]; r < first_[i + 1]; s++, r++)
      plan_[r] = {records_.record(i, s), &defs_[records_.key(i, s)], records_.key(i, s), i, -1};
  plan_generation_ = records_.generation();
  plan_nlocal_ = nlocal;
  plan_nall_ = nall;
  return true;
}

// The evaluation indices of the springs evaluate_centres() takes (centre_r_), evaluate_plane() (plane_r_) and of
// the others (other_r_), and what their results keep between steps: atom, key, and the +0 torques of centre
// attachments.
void FixParmecSpring::split_plan(int total)
{
  centre_r_.clear();
  plane_r_.clear();
  other_r_.clear();
  all_r_.resize(total);
  std::iota(all_r_.begin(), all_r_.end(), 0);
  for (int r = 0; r < total; r++) {
    const SpringDef &d = *plan_[r].def;
    SpringResult &res = results_[r];
    res.i = plan_[r].i;
    res.key = plan_[r].key;
    for (int c = 3; c < 6; c++) {
      res.ft[c] = 0.0;
      res.ft[6 + c] = -0.0;  // -(+0): part2's side is stored negated
    }
    const bool centres = d.mode == sp::DirectionMode::Follower && d.tag2 >= 0 && d.arm1_zero && d.arm2_zero &&
                         !(d.law.friction > 0.0);
    const bool plane = d.mode == sp::DirectionMode::Plane && d.tag2 >= 0 && d.arm1_zero;
    (centres ? centre_r_ : plane ? plane_r_ : other_r_).push_back(r);
  }
  centre_total_ = total;
}

// Pack the states advanced in hot_ into their records (plan order), with the force of the last committed step
// (results_[r], which only Commit evaluations write between syncs: trial and setup ones sync first): the
// records are written only here, not by every step.
void FixParmecSpring::sync_records() const
{
  if (!hot_dirty_) return;
  for (std::size_t r = 0; r < hot_.size(); r++) {
    double *slot = plan_[r].slot;
    hot_[r].pack(slot + 1);
    const SpringResult &res = results_[r];
    if (!res.apply) continue;
    for (int c = 0; c < 3; c++) slot[kForce + c] = res.ft[c];
    slot[kValid] = 1.0;
  }
  hot_dirty_ = false;
}

// Whether the local output rows (and the EQM column, which only ratio dashpots need otherwise) are written
// in this evaluation: trial and setup evaluations, steps with output (thermo, dumps: output->next), the last
// step of a run (read by the library between runs), and every step when a compute reduce, fix ave/histo,
// python or external fix exists (they read at steps of their own).
bool FixParmecSpring::output_wanted(Mode mode) const
{
  return mode != Mode::Commit || readers_every_step_ || update->ntimestep == output->next ||
         update->ntimestep == update->laststep;
}

// Output row r of plan_[r]'s spring after its evaluation (eqm < 0: not computed yet); kFailed if EQM fails.
int FixParmecSpring::output_row(const EvalContext &ctx, int r, const sp::SpringState &state, double eqm, int k)
{
  const SpringDef &d = *plan_[r].def;
  double *out = array_local[r];
  out[0] = static_cast<double>(d.id);
  state_columns(state, out + 1);
  if (eqm < 0.0 && !std::isnan(eqm)) {
    try {
      eqm = spring_eqm(ctx, d, plan_[r].i, k, d.mode == sp::DirectionMode::Constant ? d.d : state.direction);
    } catch (std::exception &e) {
      record_failure(results_[r], e.what());
      return kFailed;
    }
  }
  out[7] = eqm;
  return 0;
}

void FixParmecSpring::record_failure(SpringResult &res, const char *what)
{
  res.failure = Failure::Kernel;
  res.apply = false;
#if defined(_OPENMP)
#pragma omp critical(dembridge_spring_failure)
#endif
  failure_text_[res.key] = what;
}

void FixParmecSpring::report_failure(const SpringResult &res)
{
  const SpringDef &d = defs_[res.key];
  switch (res.failure) {
    case Failure::Part2Missing:
      second_atom_missing(res.key, " above the longest spring");
    case Failure::Kernel:
    case Failure::None:
      break;
  }
  fail_on_this_rank(lmp, FLERR, fmt::format("{}: spring {}: {}", cmd_, d.id, failure_text_[res.key]));
}

}  // namespace dembridge
