// fix parmec/spring: LAMMPS glue for the Parmec SPRING kernels. See fix_parmec_spring.h for the design
// and doc/fix_parmec_spring.md for the user syntax.
#include "fix_parmec_spring.h"
#include "definition_file.h"

#include "style_registry.h"

#include "body_rotation.h"
#include "critical_step.h"
#include "equivalent_mass.h"
#include "spring_step.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "compute.h"
#include "modify.h"
#include "neighbor.h"
#include "output.h"
#include "update.h"
#include "utils.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;
namespace sp = dembridge::springs;

namespace dembridge {

using sp::operator+;
using sp::operator-;
using sp::operator*;

namespace {

constexpr int kState = sp::SpringState::kPackedSize;
constexpr int kForce = 1 + kState;  // offset of the stored force in a slot
constexpr int kValid = kForce + 3;  // 1 once the spring has committed a step
constexpr int kCols = 8;            // id LENGTH STROKE F SF FF SS EQM

const char *const kSpringOptions[] = {"dashpot", "ratio",  "direction", "planar", "plane", "unload",
                                      "ylim",    "inactive", "offset",  "friction", "kskn"};

bool is_spring_option(const std::string &s)
{
  for (const char *o : kSpringOptions)
    if (s == o) return true;
  return false;
}

using state::is_number;

using Rot = sp::BodyRotation;

sp::Vec3 vec(const double *a) { return {a[0], a[1], a[2]}; }
bool zero(const sp::Vec3 &a) { return a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0; }

}  // namespace

FixParmecSpring::FixParmecSpring(LAMMPS *lmp, int narg, char **arg) :
    PerAtomStateFix(lmp, narg, arg, kSlot),
    reader_(lmp, cmd_, state::DefinitionReader::kTable | state::DefinitionReader::kTseries |
                           state::DefinitionReader::kFile | state::DefinitionReader::kHistory |
                           state::DefinitionReader::kStart,
            "spring", "table, tseries, spring, file, history, start, eqm, inertia or order")
{
  if (narg < 4)
    error->all(FLERR, cmd_ + ": expected definitions (table, tseries, spring, file, start) after the style name");

  local_output(kCols);
  vector_flag = 1;  // CRITICAL: [min per-spring step, min per-particle step]
  size_vector = 2;
  array_flag = 1;  // CRITICAL(perspring=, perparticle=): (h, omega, xi) per spring, then per atom
  size_array_cols = 3;
  extarray = 0;
  global_freq = 1;
  extvector = 0;

  reader_.parse(std::vector<std::string>(arg + 3, arg + narg), "command line",
                [this](const std::vector<std::string> &tok, std::size_t &i, const std::string &where) {
                  if (tok[i] == "eqm") {
                    q8_arm_ = reader_.choice(tok, i, where, {"correct", "parmec"}) == 1;
                    return true;
                  }
                  if (tok[i] == "inertia") {  // CRITICAL with the bodies' inertia tensors (Parmec front end)
                    if (i + 1 >= tok.size())
                      error->all(FLERR, cmd_ + ": inertia: expected the name of a d2_NAME 6 per-atom property");
                    inertia_name_ = tok[i + 1];
                    i += 2;
                    return true;
                  }
                  if (tok[i] == "order") {
                    parmec_order_ = reader_.choice(tok, i, where, {"lammps", "parmec"}) == 1;
                    return true;
                  }
                  return parse_spring(tok, i, where);
                });
  resolve();
  for (SpringDef &d : defs_) d.law.fused = parmec_order_;
  parmec_schedule();

  reference_geometry(snapshot_entity_atoms());
  initial_states();

  open_history(reader_.history, "spr",
               {"LENGTH", "STROKE", "F", "SF", "FF", "SS"});
}

// Resolve table/TSERIES IDs (forward references allowed), validate each law, size the per-atom state.
void FixParmecSpring::resolve()
{
  for (std::size_t s = 0; s < defs_.size(); s++) {
    SpringDef &d = defs_[s];
    const LawNames &n = names_[s];
    const std::string who = cmd_ + ": spring " + std::to_string(d.id) + ": ";
    d.law.spring = reader_.table(n.spring, who, "spring");
    if (!n.dashpot.empty()) d.law.dashpot = reader_.table(n.dashpot, who, "dashpot");
    if (!n.unload.empty()) d.law.unload = reader_.table(n.unload, who, "unload");
    if (!n.offset.empty()) {
      const sp::TimeSeries *ts = reader_.tseries(n.offset, who, "offset");
      try {
        d.law.offset = &ts->as_table("offset");
      } catch (std::invalid_argument &e) {
        error->all(FLERR, who + "offset " + n.offset + ": " + e.what());
      }
    }
    try {
      d.law.validate();
    } catch (std::invalid_argument &e) {
      std::string used = " (spring table " + n.spring;
      if (!n.dashpot.empty()) used += ", dashpot table " + n.dashpot;
      if (!n.unload.empty()) used += ", unload table " + n.unload;
      if (!n.offset.empty()) used += ", offset tseries " + n.offset;
      error->all(FLERR, who + e.what() + used + ")");
    }
  }
  names_.clear();
  std::vector<long> ids;
  std::vector<std::pair<long, long>> atoms;
  for (std::size_t s = 0; s < defs_.size(); s++) {
    id_index_[defs_[s].id] = static_cast<int>(s);
    ids.push_back(defs_[s].id);
    atoms.emplace_back(defs_[s].tag1, defs_[s].tag2);
  }
  define_entities("spring", ids, atoms, 6);  // state on part1; force (3) and torque (3) on each atom
}

// Parmec's spring loop (forces.ispc, one task) walks the springs sorted by (part1, part2) and keeps one
// running sum per body side: the forces of consecutive springs with the same part1 (a "run") are summed,
// then added to part1's force when part1 changes; likewise for part2 among the springs with a part2 (a
// spring to space does not end a part2 run), subtracted when part2 changes; at the end the part1 sum, then
// the part2 sum. rank = (the moment its run is added) * n + (position in the sorted order), so an atom's
// contributions sorted by rank are its runs in Parmec's order, each in spring order.
void FixParmecSpring::parmec_schedule()
{
  const int n = static_cast<int>(defs_.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [this](int a, int b) {
    return defs_[a].tag1 != defs_[b].tag1 ? defs_[a].tag1 < defs_[b].tag1 : defs_[a].tag2 < defs_[b].tag2;
  });
  std::vector<int> run_of(2 * std::size_t(n), -1), added;  // run of each (spring, side); when a run is added
  int jrun = -1, krun = -1, moment = 0;
  tagint j0 = 0, k0 = 0;
  for (int p = 0; p < n; p++) {
    const SpringDef &d = defs_[order[p]];
    if (jrun < 0 || d.tag1 != j0) {
      if (jrun >= 0) added[jrun] = moment++;
      jrun = static_cast<int>(added.size());
      added.push_back(-1);
      j0 = d.tag1;
    }
    run_of[2 * order[p]] = jrun;
    if (d.tag2 < 0) continue;
    if (krun < 0 || d.tag2 != k0) {
      if (krun >= 0) added[krun] = moment++;
      krun = static_cast<int>(added.size());
      added.push_back(-1);
      k0 = d.tag2;
    }
    run_of[2 * order[p] + 1] = krun;
  }
  if (jrun >= 0) added[jrun] = moment++;
  if (krun >= 0) added[krun] = moment++;
  parmec_rank_.assign(2 * std::size_t(n), -1);
  for (int p = 0; p < n; p++)
    for (int side = 0; side < 2; side++) {
      const int r = run_of[2 * order[p] + side];
      if (r >= 0) parmec_rank_[2 * order[p] + side] = static_cast<long long>(added[r]) * n + p;
    }
}

// LENGTH STROKE F SF FF SS of a spring state: the output columns 2-7 and the history columns.
static void state_columns(const sp::SpringState &st, double *out)
{
  out[0] = st.length;
  out[1] = st.stroke;
  out[2] = st.force_total;
  out[3] = st.force_elastic;
  out[4] = st.friction_force;
  out[5] = st.code;
}

// History columns of one spring: those of its last committed step.
void FixParmecSpring::history_values(const double *rec, double *out) const
{
  sp::SpringState st;
  st.unpack(rec + 1);
  state_columns(st, out);
}

// ---------------------------------------------------------------------------------------------------
// parsing

bool FixParmecSpring::parse_spring(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  if (tok[i] != "spring") return false;
  // spring SID I1 P1 I2 P2 TID [options], P = x y z | centre
  state::EntityWords w(reader_, tok, i, where, "spring SID part1 x1 y1 z1|centre part2 x2 y2 z2|centre TABLE [options]");
  SpringDef d;
  LawNames n;
  d.id = w.id(spring_ids_);
  auto point = [&](bool &centre, sp::Vec3 &P, const std::string &what) {
    const std::string &t = w.next(what);
    if (t == "centre" || t == "center") {
      centre = true;
      return;
    }
    P[0] = w.number(t, what + " x");
    P[1] = w.number(w.next(what + " y"), what + " y");
    P[2] = w.number(w.next(what + " z"), what + " z");
  };
  d.tag1 = w.part1();
  point(d.centre1, d.P1, "point1");
  d.tag2 = w.part2(d.tag1, "spatial anchor");
  point(d.centre2, d.P2, "point2");
  if (d.centre2 && d.tag2 < 0) w.fail("point2 of a spatial anchor (part2 = -1) needs coordinates, not 'centre'");
  n.spring = w.next("spring table ID");
  if (is_spring_option(n.spring) || is_number(n.spring))
    w.fail("expected the spring table ID after point2, got '" + n.spring + "'");

  bool have_dir = false, planar = false, plane = false;
  sp::Vec3 dir{};
  while (w.more() && is_spring_option(w.peek())) {
    const std::string o = w.next("option");
    if (o == "dashpot") {
      n.dashpot = w.next("dashpot table ID");
    } else if (o == "ratio") {
      d.law.damping_ratio = w.number(w.next("ratio value"), "ratio");
      if (d.law.damping_ratio < 0) w.fail("ratio must be >= 0");
    } else if (o == "direction") {
      for (int c = 0; c < 3; c++) dir[c] = w.number(w.next("direction component"), "direction");
      have_dir = true;
    } else if (o == "planar") {
      planar = true;
    } else if (o == "plane") {
      for (int c = 0; c < 3; c++) d.normal[c] = w.number(w.next("plane normal component"), "plane normal");
      plane = true;
    } else if (o == "unload") {
      n.unload = w.next("unload table ID");
    } else if (o == "ylim") {
      d.law.ylim_comp = w.number(w.next("ylim compression limit"), "ylim");
      d.law.ylim_tens = w.number(w.next("ylim tension limit"), "ylim");
    } else if (o == "inactive") {
      d.inactive = true;
    } else if (o == "offset") {
      n.offset = w.next("offset TSERIES ID");
    } else if (o == "friction") {
      d.law.friction = w.number(w.next("friction value"), "friction");
    } else if (o == "kskn") {
      d.law.kskn = w.number(w.next("kskn value"), "kskn");
    }
  }
  if (planar && !have_dir) w.fail("'planar' needs 'direction dx dy dz' (the plane normal)");
  w.check([&] {
    if (plane) {
      d.mode = sp::DirectionMode::Plane;  // direction/planar ignored (spec §2.1)
      d.normal = sp::unit_direction(d.normal, "plane normal");
    } else if (have_dir) {
      d.mode = planar ? sp::DirectionMode::Planar : sp::DirectionMode::Constant;
      d.d = sp::unit_direction(dir, "direction");
    }
  });
  defs_.push_back(d);
  names_.push_back(n);
  return w.accept(i);
}

// ---------------------------------------------------------------------------------------------------
// reference geometry (spec §2.1; kernel doc §5): body-frame arms, anchors, stroke0

// snap: the reference centre (unwrapped) and orientation of every spring's atoms, from their owners.
void FixParmecSpring::reference_geometry(const std::vector<state::AtomSnapshot> &snap)
{
  for (std::size_t s = 0; s < defs_.size(); s++) {
    SpringDef &d = defs_[s];
    const state::AtomSnapshot &a1 = snap[2 * s], &a2 = snap[2 * s + 1];
    const sp::Vec3 X1 = vec(a1.x);
    const Rot R1 = Rot::of(a1.q);
    const sp::Vec3 P1 = d.centre1 ? X1 : d.P1;
    d.X1ref = X1;
    auto min_image = [&](sp::Vec3 v) {
      domain->minimum_image(FLERR, v[0], v[1], v[2]);
      return v;
    };
    auto snap = [](sp::Vec3 arm, const sp::Vec3 &X) {
      const double tol = 1e-12 * std::max(1.0, sp::norm(X));
      return sp::norm(arm) <= tol ? sp::Vec3{0, 0, 0} : arm;
    };
    d.arm1 = d.centre1 ? sp::Vec3{0, 0, 0} : R1.apply_t(snap(min_image(P1 - X1), X1));
    if (d.tag2 >= 0) {
      const sp::Vec3 X2 = vec(a2.x);
      const Rot R2 = Rot::of(a2.q);
      // part2's point (or plane point) as seen from P1 through the minimum image
      sp::Vec3 P2 = d.centre2 ? X2 : d.P2;
      P2 = P1 + min_image(P2 - P1);
      const sp::Vec3 X2n = P1 + min_image(X2 - P1);
      d.X2ref = X2n;
      if (d.mode == sp::DirectionMode::Plane) {
        const sp::Vec3 Q = sp::plane_anchor(P1, P2, d.normal);
        d.arm2 = R2.apply_t(snap(Q - X2n, X2n));
        d.nref = R2.apply_t(d.normal);
        d.stroke0 = 0.0;
      } else {
        d.arm2 = (d.centre2 ? sp::Vec3{0, 0, 0} : R2.apply_t(snap(P2 - X2n, X2n)));
        d.stroke0 = sp::reference_stroke0(d.mode, d.d, P1, P2);
      }
    } else {
      if (d.mode == sp::DirectionMode::Plane) {
        d.arm2 = sp::plane_anchor(P1, d.P2, d.normal);
        d.nref = d.normal;
        d.stroke0 = 0.0;
      } else {
        d.arm2 = d.P2;
        d.stroke0 = sp::reference_stroke0(d.mode, d.d, P1, d.P2);
      }
    }
  }
}

void FixParmecSpring::initial_states()
{
  initial_records([this](int s, double *rec) {
    sp::SpringState::initial(defs_[s].law, defs_[s].inactive).pack(rec + 1);
  });
}

// ---------------------------------------------------------------------------------------------------
// run-time checks

void FixParmecSpring::init()
{
  size_array_rows = static_cast<int>(defs_.size() + atom->natoms);
  check_run_style_and_ghosts("springs between two atoms need ghost velocities");
  const bool hasq = atom->quat_flag && atom->quat;
  for (SpringDef &d : defs_) {
    d.arm1_zero = zero(d.arm1);
    d.arm2_zero = d.tag2 < 0 || zero(d.arm2);
    const bool off = !zero(d.arm1) || (d.tag2 >= 0 && !zero(d.arm2));
    const bool moving_plane = d.mode == sp::DirectionMode::Plane && d.tag2 >= 0;
    if ((off || moving_plane) && !hasq)
      error->all(FLERR, cmd_ + ": spring " + std::to_string(d.id) +
                            (off ? ": attachment point away from the atom centre" : ": plane attached to part2") +
                            " rotates with the atom and needs per-atom quaternions: use atom_style bpm/sphere with "
                            "fix nve/bpm/sphere, or attach at the centre ('centre' or the atom's coordinates)");
    if (off && !atom->torque_flag)
      error->all(FLERR, cmd_ + ": spring " + std::to_string(d.id) + ": off-centre attachment needs per-atom torque");
    if (d.law.needs_equivalent_mass() && !atom->rmass_flag && !atom->mass)
      error->all(FLERR, cmd_ + ": spring " + std::to_string(d.id) + ": ratio dashpot needs atom masses");
  }
  check_record_count();  // one state per spring, on part1's owner
  // Readers of the local output outside output steps (see output_wanted): they may read on any step.
  readers_every_step_ = false;
  for (const Compute *c : modify->get_compute_list())
    readers_every_step_ = readers_every_step_ || utils::strmatch(c->style, "^reduce");
  for (const Fix *f : modify->get_fix_list())
    readers_every_step_ = readers_every_step_ || utils::strmatch(f->style, "^ave/histo") ||
                          utils::strmatch(f->style, "^python") || utils::strmatch(f->style, "^external");
  rigid_ = nullptr;
  if (parmec_order_) {
    const auto rigid = modify->get_fix_by_style("^parmec/rigid$");
    if (rigid.empty())
      error->all(FLERR, cmd_ + ": order parmec: needs fix parmec/rigid (the springs use the rotations it keeps)");
    rigid_ = rigid.front();
  }
}

void FixParmecSpring::setup(int)
{
  cutghost_ = comm->get_comm_cutoff();
  // Rank-independent length check: the centre distance of two connected atoms must not exceed the
  // ghost cutoff, otherwise part2 is not a ghost of part1's owner on some decompositions.
  const Farthest far = farthest_beyond(cutghost_);
  if (far.key >= 0) {
    const SpringDef &d = defs_[far.key];
    error->all(FLERR, fmt::format("{}: spring {} between atoms {} and {} is {:.6g} long, longer than the ghost cutoff "
                                  "{:.6g}: raise 'comm_modify cutoff' above the longest spring",
                                  cmd_, d.id, d.tag1, d.tag2, far.distance, cutghost_));
  }
  evaluate(Mode::Setup);
}

void FixParmecSpring::min_setup(int)
{
  cutghost_ = comm->get_comm_cutoff();
  evaluate(Mode::Trial);
}

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
  ctx.inertia = inertia_array();
  ctx.tag = atom->tag;
  ctx.nall = nlocal + atom->nghost;
  ctx.periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  ctx.rot = rigid_ ? rigid_->array_atom : nullptr;
  // Local and ghost indices change only when the neighbour lists are rebuilt (exchange, sort, borders).
  ctx.recheck = ctx.periodic || neighbor->ncalls != plan_builds_;
  plan_builds_ = neighbor->ncalls;
  ctx.fill = output_wanted(mode);
  auto spring = parmec_order_ ? &FixParmecSpring::evaluate_spring<true> : &FixParmecSpring::evaluate_spring<false>;
  // Committed steps in the default order: the centre-to-centre point springs and the planes carried by part2
  // from part1's centre by their own loops (evaluate_centres, evaluate_plane)
  const bool split = mode == Mode::Commit && !parmec_order_;
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
  {
#pragma omp single nowait
    threads_used_ = std::max(threads_used_, omp_get_num_threads());
    if (split) {
      const int nc = static_cast<int>(centre_r_.size()), np = static_cast<int>(plane_r_.size());
      const int no = static_cast<int>(other_r_.size());
      if (ctx.body_rot) {
#pragma omp for schedule(static)
        for (int j = 0; j < ctx.nall; j++) atom_rot_[j] = Rot::of(ctx.quat[j]);
      }
#pragma omp for schedule(static) nowait
      for (int n = 0; n < nc; n++) flags |= evaluate_centres(ctx, centre_r_[n]);
#pragma omp for schedule(static) nowait
      for (int n = 0; n < np; n++) flags |= evaluate_plane(ctx, plane_r_[n]);
#pragma omp for schedule(static)
      for (int n = 0; n < no; n++) flags |= (this->*spring)(ctx, other_r_[n]);
    } else {
#pragma omp for schedule(static)
      for (int r = 0; r < total; r++) flags |= (this->*spring)(ctx, r);
    }
  }
#else
  if (split) {
    if (ctx.body_rot)
      for (int j = 0; j < ctx.nall; j++) atom_rot_[j] = Rot::of(ctx.quat[j]);
    for (const int r : centre_r_) flags |= evaluate_centres(ctx, r);
    for (const int r : plane_r_) flags |= evaluate_plane(ctx, r);
    for (const int r : other_r_) flags |= (this->*spring)(ctx, r);
  } else {
    for (int r = 0; r < total; r++) flags |= (this->*spring)(ctx, r);
  }
#endif

  if (mode == Mode::Commit) hot_dirty_ = true;

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
      for (const state::LocalIncidence::Term *t = t0; t != t1; ++t) {
        const double *v = results_[t->r].ft + 6 * t->side;  // signs applied (part2's side stored negated)
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

// Atom i's contributions (local results t0..t1 and the entries received for it) added to f and torque run
// by run in Parmec's order (parmec_schedule): each run summed from its first spring on, then added.
void FixParmecSpring::add_in_parmec_order(int i, const state::LocalIncidence::Term *t0,
                                          const state::LocalIncidence::Term *t1, double *f, double *torque) const
{
  struct Item {
    long long rank;
    const double *v;  // with its sign
  };
  Item items[2 * state::OrderedSums::kMaxOrdered];
  const int cap = 2 * state::OrderedSums::kMaxOrdered;
  int n = 0;
  for (const state::LocalIncidence::Term *t = t0; t != t1 && n < cap; ++t) {
    const SpringResult &res = results_[t->r];
    items[n++] = {parmec_rank_[2 * std::size_t(t->key) + t->side], res.ft + 6 * t->side};
  }
  for (int c = 0; c < sums_.count(i) && n < cap; c++) {  // received: part2 sides, sign applied
    const double *e = sums_.entry_of(i, c);
    items[n++] = {parmec_rank_[2 * static_cast<std::size_t>(e[0]) + 1], e + 1};
  }
  std::sort(items, items + n, [](const Item &a, const Item &b) { return a.rank < b.rank; });
  const long long nspr = static_cast<long long>(defs_.size());
  double run[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int m = 0; m < n; m++) {
    const bool first = m == 0 || items[m].rank / nspr != items[m - 1].rank / nspr;
    for (int c = 0; c < 6; c++) run[c] = (first ? 0.0 : run[c]) + items[m].v[c];
    if (m + 1 < n && items[m + 1].rank / nspr == items[m].rank / nspr) continue;
    for (int c = 0; c < 3; c++) f[c] += run[c];
    if (torque)
      for (int c = 0; c < 3; c++) torque[c] += run[3 + c];
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

// Pack the states advanced in hot_ into their records (plan order).
void FixParmecSpring::sync_records() const
{
  if (!hot_dirty_) return;
  for (std::size_t r = 0; r < hot_.size(); r++) hot_[r].pack(plan_[r].slot + 1);
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

// The law's step of spring d (atoms i, k) in this frame: advances state, returns the force on part1; eqm: the
// EQM when it was computed (ratio dashpot or output wanted). Throws the kernels' errors.
[[gnu::always_inline]] inline sp::Vec3 FixParmecSpring::law_step(const EvalContext &ctx, const SpringDef &d, int i, int k,
                                                                 const sp::SpringFrame &frame, sp::SpringState &state,
                                                                 double &eqm) const
{
  sp::SpringStepInput in;
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
  return sp::advance_spring(d.law, state, frame, in).on_part1;
}

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
    const double dist = sp::norm(vec(x[k]) - vec(x[i]));
    if (dist > cutghost_) {
      res.failure = Failure::TooLong;
      res.value = dist;
      return flags | kFailed;
    }
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
    if (mode == Mode::Commit) {
      for (int c = 0; c < 3; c++) slot[kForce + c] = F[c];
      slot[kValid] = 1.0;
    }
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

// The committed step of a point spring between two atom centres (centre_r_: follower, no friction, default
// order), the bench's and most lattices' spring: evaluate_spring's arithmetic without the arm terms. Equal
// bitwise: the points are the centres + 0 (as p = x + a with a = +0), the distance check's length is the
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
  if (frame.distance > cutghost_) {
    res.failure = Failure::TooLong;
    res.value = frame.distance;
    return flags | kFailed;
  }
  frame.len = frame.distance;
  frame.z = sp::unit_of(w, frame.len, false);
  const double *vi = v[i], *vk = v[k];
  frame.velocity = sp::dot(frame.z, sp::Vec3{vk[0] - vi[0], vk[1] - vi[1], vk[2] - vi[2]});
  return flags | commit_force(ctx, r, k, frame, nullptr);
}

// The committed law step of spring r of the own loops (evaluate_centres, evaluate_plane) in this frame: its force
// in the record and in results_[r] (F on part1, -F on part2), part2's torque -(b x F) if arm2 (b) is given, else
// split_plan's -0, part1's split_plan's +0; its output row if wanted. Returns kFailed or 0.
[[gnu::always_inline]] inline int FixParmecSpring::commit_force(const EvalContext &ctx, int r, int k,
                                                                const sp::SpringFrame &frame, const sp::Vec3 *arm2)
{
  PlanItem &item = plan_[r];
  SpringResult &res = results_[r];
  sp::SpringState &state = hot_[r];
  double eqm = -1.0;
  sp::Vec3 F;
  try {
    F = law_step(ctx, *item.def, item.i, k, frame, state, eqm);
  } catch (std::exception &e) {
    record_failure(res, e.what());
    return kFailed;
  }
  double *slot = item.slot;
  for (int c = 0; c < 3; c++) slot[kForce + c] = F[c];
  slot[kValid] = 1.0;
  res.apply = true;
  res.k = k;
  for (int c = 0; c < 3; c++) {
    res.ft[c] = F[c];
    res.ft[6 + c] = -F[c];
  }
  if (arm2) {
    const sp::Vec3 tb = sp::cross(*arm2, F);
    for (int c = 0; c < 3; c++) res.ft[9 + c] = -tb[c];
  }
  if (!ctx.fill) return 0;
  return output_row(ctx, r, state, eqm, k);
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
  const double dist = sp::norm(xk - xi);
  if (dist > cutghost_) {
    res.failure = Failure::TooLong;
    res.value = dist;
    return flags | kFailed;
  }
  const sp::Vec3 zero3{0, 0, 0};
  const Rot Rk = ctx.body_rot ? ctx.body_rot[k] : ctx.quat ? Rot::of(ctx.quat[k]) : Rot::identity();
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
    case Failure::TooLong:
      error->one(FLERR, fmt::format("{}: spring {} between atoms {} and {} is {:.6g} long, longer than the ghost "
                                    "cutoff {:.6g}: raise 'comm_modify cutoff' above the longest spring",
                                    cmd_, d.id, d.tag1, d.tag2, res.value, cutghost_));
    case Failure::Kernel:
    case Failure::None:
      break;
  }
  error->one(FLERR, fmt::format("{}: spring {}: {}", cmd_, d.id, failure_text_[res.key]));
}

void FixParmecSpring::post_force(int)
{
  evaluate(Mode::Commit);
}

// Under 'package omp N' the spring loop is threaded (OpenMP); say so once per run.
void FixParmecSpring::post_run()
{
  const int used = threads_used_;
  int most = 0;
  MPI_Allreduce(&used, &most, 1, MPI_INT, MPI_MAX, world);
  if (most > 1 && comm->me == 0) utils::logmesg(lmp, "{}: spring loop on {} OpenMP threads\n", cmd_, most);
  threads_used_ = 0;
}

// CRITICAL (spec §13, kernel doc §5): per spring from the spring's EQM along its current direction
// (Constant/Planar: d; before the first step the eigen branch); per particle from every spring attached
// to it. Collective: every rank gathers the (few) numbers of all springs, then estimates its own atoms.
double FixParmecSpring::compute_vector(int n)
{
  if (crit_step_ != update->ntimestep) critical();
  crit_step_ = update->ntimestep;
  return crit_[n];
}

double FixParmecSpring::compute_array(int i, int j)
{
  if (crit_step_ != update->ntimestep) critical();
  crit_step_ = update->ntimestep;
  const std::size_t k = 3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(j);
  return k < crit_table_.size() ? crit_table_[k] : 0.0;
}

void FixParmecSpring::critical()
{
  constexpr int kRec = 14;  // tag1 tag2 k_s e dir(3) planar arm1(3) arm2(3)
  const double *rmass = atom->rmass_flag ? atom->rmass : nullptr;
  auto mass_of = [&](int i) { return rmass ? rmass[i] : atom->mass[atom->type[i]]; };
  auto body = [&](int i) {
    sp::BodyMass b;
    b.mass = mass_of(i);
    const std::array<double, 9> J = critical_inertia(i, b.mass);
    if (J[1] == 0.0 && J[2] == 0.0 && J[5] == 0.0) {  // principal axes (spheres): 1/J, no cofactor rounding
      for (int c = 0; c < 3; c++) b.inv_inertia[4 * c] = J[4 * c] > 0.0 ? 1.0 / J[4 * c] : 0.0;
      return b;
    }
    const double det = J[0] * (J[4] * J[8] - J[5] * J[7]) - J[1] * (J[3] * J[8] - J[5] * J[6]) +
                       J[2] * (J[3] * J[7] - J[4] * J[6]);
    if (det > 0.0) b.inv_inertia = sp::parmec_inverse(J);  // as Parmec's critical_perspring (its eqm's J⁻¹)
    return b;
  };
  sync_records();
  std::vector<double> mine, mine_rows;  // mine_rows: (table row, h, omega, xi)
  double hs = INFINITY;
  for (int i = 0; i < atom->nlocal; i++) {
    for (int s = 0; s < records_.count(i); s++) {
      const double *slot = records_.record(i, s);
      const SpringDef &d = defs_[records_.key(i, s)];
      sp::SpringState st;
      st.unpack(slot + 1);
      const bool fixed_dir = d.mode == sp::DirectionMode::Constant;
      const sp::Vec3 zdir = fixed_dir ? d.d : st.direction;
      const sp::BodyMass b1 = body(i);
      double m_s;
      int k = -1;
      if (d.tag2 >= 0) {
        k = atom->map(d.tag2);
        if (k < 0)
          error->one(FLERR, fmt::format("{}: CRITICAL: spring {}: part2 atom {} is not available (run at least "
                                        "'run 0' first, or raise 'comm_modify cutoff')", cmd_, d.id, d.tag2));
        const sp::BodyMass b2 = body(k);
        m_s = sp::equivalent_mass(b1, d.arm1, &b2, d.arm2, zdir);
      } else {
        m_s = sp::equivalent_mass(b1, d.arm1, nullptr, {0, 0, 0}, zdir);
      }
      const sp::CriticalEstimate es = sp::spring_critical(d.law, m_s);
      hs = std::min(hs, es.step);
      const double row[4] = {double(records_.key(i, s)), es.step, es.omega, es.xi};
      mine_rows.insert(mine_rows.end(), row, row + 4);
      const bool planar = d.mode == sp::DirectionMode::Planar;
      const sp::Vec3 adir = planar ? d.d : zdir;
      const double rec[kRec] = {double(d.tag1), double(d.tag2), d.law.spring->max_abs_slope(),
                                sp::spring_max_damping(d.law, m_s), adir[0], adir[1], adir[2], planar ? 1.0 : 0.0,
                                d.arm1[0], d.arm1[1], d.arm1[2], d.arm2[0], d.arm2[1], d.arm2[2]};
      mine.insert(mine.end(), rec, rec + kRec);
    }
  }
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < comm->nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> all(displs.back() + counts.back());
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);

  std::unordered_map<tagint, sp::ParticleCritical> particles;
  std::unordered_map<tagint, int> owned;
  for (int i = 0; i < atom->nlocal; i++) owned[atom->tag[i]] = i;
  for (std::size_t r = 0; r + kRec <= all.size(); r += kRec) {
    const double *e = &all[r];
    const sp::Vec3 dir{e[4], e[5], e[6]};
    for (int side = 0; side < 2; side++) {
      const tagint t = static_cast<tagint>(e[side]);
      if (t < 0 || !owned.count(t)) continue;
      particles[t].add_spring(e[2], e[3], dir, e[7] != 0.0, {e[8 + 3 * side], e[9 + 3 * side], e[10 + 3 * side]});
    }
  }
  double hp = INFINITY;
  for (auto &kv : particles) {
    const int i = owned[kv.first];
    std::array<double, 9> J = critical_inertia(i, mass_of(i));
    if (!(J[0] > 0.0)) J = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // no radius, no inertia property
    const sp::CriticalEstimate ep = kv.second.estimate(mass_of(i), J);
    hp = std::min(hp, ep.step);
    const double row[4] = {double(defs_.size()) + double(kv.first - 1), ep.step, ep.omega, ep.xi};
    mine_rows.insert(mine_rows.end(), row, row + 4);
  }
  // every rank gets the whole table (few numbers: one row per spring and per atom)
  const std::size_t nrows = defs_.size() + static_cast<std::size_t>(atom->natoms);
  std::vector<double> table(3 * nrows, 0.0);
  for (std::size_t r = defs_.size(); r < nrows; r++) table[3 * r] = DBL_MAX;
  n = static_cast<int>(mine_rows.size());
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < comm->nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> rows(displs.back() + counts.back());
  MPI_Allgatherv(mine_rows.data(), n, MPI_DOUBLE, rows.data(), counts.data(), displs.data(), MPI_DOUBLE, world);
  for (std::size_t r = 0; r + 4 <= rows.size(); r += 4) {
    const std::size_t at = 3 * static_cast<std::size_t>(rows[r]);
    if (at + 2 < table.size()) std::copy(&rows[r + 1], &rows[r + 4], &table[at]);
  }
  crit_table_.swap(table);
  MPI_Allreduce(&hs, &crit_[0], 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(&hp, &crit_[1], 1, MPI_DOUBLE, MPI_MIN, world);
}

// ---------------------------------------------------------------------------------------------------
// restart

// Global restart: the reference geometry, so that a restarted run does not re-reference the springs
// to the current positions. Layout marked negative: 16 values per spring (with the reference centres);
// positive: 10 (files written before the reference centres were stored).
void FixParmecSpring::write_restart(FILE *fp)
{
  write_entity_restart(fp, 16, -1.0, [this](int s, double *o) {
    const SpringDef &d = defs_[s];
    for (int c = 0; c < 3; c++) {
      o[c] = d.arm1[c];
      o[3 + c] = d.arm2[c];
      o[6 + c] = d.nref[c];
    }
    o[9] = d.stroke0;
    for (int c = 0; c < 3; c++) {
      o[10 + c] = d.X1ref[c];
      o[13 + c] = d.X2ref[c];
    }
  });
}

void FixParmecSpring::restart(char *buf)
{
  read_entity_restart(buf, [](bool negative) { return negative ? 16 : 10; }, [this](int s, const double *o, int per) {
    SpringDef &d = defs_[s];
    for (int c = 0; c < 3; c++) {
      d.arm1[c] = o[c];
      d.arm2[c] = o[3 + c];
      d.nref[c] = o[6 + c];
    }
    d.stroke0 = o[9];
    if (per == 16)
      for (int c = 0; c < 3; c++) {
        d.X1ref[c] = o[10 + c];
        d.X2ref[c] = o[13 + c];
      }
    else if (q8_arm_)
      error->all(FLERR, cmd_ + ": 'eqm parmec' needs the reference centres, which this (older) restart file "
                               "does not hold");
  });
}

double **FixParmecSpring::inertia_array() const
{
  if (inertia_name_.empty()) return nullptr;
  int flag = 0, cols = 0;
  const int ij = atom->find_custom(inertia_name_.c_str(), flag, cols);
  if (ij < 0 || flag != 1 || cols != 6)
    error->all(FLERR, cmd_ + ": inertia: '" + inertia_name_ + "' is not a per-atom array of 6 doubles (fix "
                              "property/atom d2_" + inertia_name_ + " 6 ghost yes)");
  return atom->darray[ij];
}

std::array<double, 9> FixParmecSpring::critical_inertia(int i, double mass) const
{
  if (double **J = inertia_array()) {
    const double *r = J[i];
    return {r[0], r[3], r[4], r[3], r[1], r[5], r[4], r[5], r[2]};
  }
  const double J = atom->radius_flag ? 0.4 * mass * atom->radius[i] * atom->radius[i] : 0.0;
  return {J, 0, 0, 0, J, 0, 0, 0, J};
}

// EQM (spec §12) of spring d along dir (zero: largest point mass) of its atoms i (part1) and k (part2, or
// -1): with their inertia tensors ('inertia NAME', Parmec's J⁻¹ as eqm() uses it), else the sphere inertia
// 0.4 m r^2. q8_arm_: Parmec's spring-force arm 2X - P (quirk Q8).
// Inline: the isotropic branch runs for every spring every step; the general one is out of line.
inline double FixParmecSpring::spring_eqm(const EvalContext &c, const SpringDef &d, int i, int k, const sp::Vec3 &dir) const
{
  if (!c.rmass && !c.mass) return NAN;  // no masses: EQM undefined (a ratio dashpot is an ERROR in init)
  auto mass_of = [&](int j) { return c.rmass ? c.rmass[j] : c.mass[c.type[j]]; };
  if (!q8_arm_ && !zero(dir) && !c.inertia) {
    // isotropic inertia: d^T M^-1 d = |d|^2/m + (|A|^2 |d|^2 - (A.d)^2)/J per body (the kernel's
    // equivalent_mass without the 3x3 matrices; equal to round-off)
    const double dd = sp::dot(dir, dir);
    double lambda = 0.0;
    auto add = [&](int j, const sp::Vec3 &A, bool centre) {
      const double m = mass_of(j);
      lambda += dd / m;
      if (centre) return;  // a centre point: the term below is exactly 0 (finite directions)
      const double J = c.radius ? 0.4 * m * c.radius[j] * c.radius[j] : 0.0;
      if (J > 0.0) {
        const double ad = sp::dot(A, dir);
        lambda += (sp::dot(A, A) * dd - ad * ad) / J;
      }
    };
    add(i, d.arm1, d.arm1_zero);
    if (k >= 0) add(k, d.arm2, d.arm2_zero);
    if (!(lambda > 0.0)) throw std::invalid_argument("EQM: the inverse mass matrix is not positive along the direction");
    return 1.0 / lambda;
  }
  return spring_eqm_general(c, d, i, k, dir);
}

// EQM with the full 3x3 inverse inertia (zero direction: largest point mass; 'eqm parmec': Q8 arm).
// The tensor is referential, as in Parmec's eqm() (its arms and J⁻¹ are the reference ones).
double FixParmecSpring::spring_eqm_general(const EvalContext &c, const SpringDef &d, int i, int k,
                                           const sp::Vec3 &dir) const
{
  auto mass_of = [&](int j) { return c.rmass ? c.rmass[j] : c.mass[c.type[j]]; };
  auto body = [&](int j, const sp::Vec3 &X) {
    if (c.inertia && c.inertia[j][0] > 0.0)  // (an atom without a tensor: the sphere's, as CRITICAL)
      return sp::BodyMass::from_inertia_list(mass_of(j), c.inertia[j], q8_arm_ ? X : sp::Vec3{});
    sp::BodyMass b;
    b.mass = mass_of(j);
    const double J = c.radius ? 0.4 * b.mass * c.radius[j] * c.radius[j] : 0.0;
    const double inv = J > 0.0 ? 1.0 / J : 0.0;
    b.inv_inertia = {inv, 0, 0, 0, inv, 0, 0, 0, inv};
    if (q8_arm_) b.centre = X;
    return b;
  };
  // Correct arm: centre 0, point = body-frame arm (A = -arm). Q8: centre X0, point X0 + arm.
  const sp::BodyMass b1 = body(i, d.X1ref);
  const sp::Vec3 p1 = q8_arm_ ? d.X1ref + d.arm1 : d.arm1;
  const auto arm = q8_arm_ ? sp::EqmArm::ParmecQ8 : sp::EqmArm::Correct;
  if (k >= 0) {
    const sp::BodyMass b2 = body(k, d.X2ref);
    return sp::equivalent_mass(b1, p1, &b2, q8_arm_ ? d.X2ref + d.arm2 : d.arm2, dir, arm, parmec_order_);
  }
  return sp::equivalent_mass(b1, p1, nullptr, {0, 0, 0}, dir, arm, parmec_order_);
}

int FixParmecSpring::spring_index(long spring_id) const
{
  auto it = id_index_.find(spring_id);
  return it == id_index_.end() ? -1 : it->second;
}

// The slot of a spring whose state this rank owns, or null. The (spring -> atom, record) index is rebuilt
// only after records moved (exchange, sort, restart), so lookups are O(1) otherwise.
const double *FixParmecSpring::owned_slot(int spring) const
{
  sync_records();
  const auto w = where_.find(records_, atom->nlocal, static_cast<int>(defs_.size()), spring);
  return w.first >= 0 ? records_.record(w.first, w.second) : nullptr;
}

namespace {
double state_entity(const sp::SpringState &st, FixParmecSpring::Entity e)
{
  switch (e) {
    case FixParmecSpring::Entity::Length: return st.length;
    case FixParmecSpring::Entity::Stroke: return st.stroke;
    case FixParmecSpring::Entity::F: return st.force_total;
    case FixParmecSpring::Entity::SF: return st.force_elastic;
    case FixParmecSpring::Entity::FF: return st.friction_force;
    case FixParmecSpring::Entity::SS: return st.code;
    default: return NAN;
  }
}
}  // namespace

double FixParmecSpring::entity_value(int spring, Entity e) const
{
  if (e == Entity::EQM) {  // from the output rows of the last evaluation
    if (spring < 0 || spring >= static_cast<int>(defs_.size())) return NAN;
    for (int r = 0; r < size_local_rows; r++)
      if (array_local[r][0] == static_cast<double>(defs_[spring].id)) return array_local[r][7];
    return NAN;
  }
  const double *slot = owned_slot(spring);
  if (!slot) return NAN;
  sp::SpringState st;
  st.unpack(slot + 1);
  return state_entity(st, e);
}

void FixParmecSpring::gather_entity(Entity e, std::vector<double> &out)
{
  sync_records();
  std::vector<double> mine(defs_.size(), 0.0);
  if (e == Entity::EQM) {
    for (int r = 0; r < size_local_rows; r++) {
      auto it = id_index_.find(std::lround(array_local[r][0]));
      if (it != id_index_.end()) mine[it->second] = array_local[r][7];
    }
  } else {
    sp::SpringState st;
    for (int i = 0; i < atom->nlocal; i++)
      for (int s = 0; s < records_.count(i); s++) {
        st.unpack(records_.record(i, s) + 1);
        mine[records_.key(i, s)] = state_entity(st, e);
      }
  }
  out.assign(defs_.size(), 0.0);
  MPI_Allreduce(mine.data(), out.data(), static_cast<int>(mine.size()), MPI_DOUBLE, MPI_SUM, world);
}

bool FixParmecSpring::set_state_code(int spring, int code)
{
  if (code < sp::kRegular) error->one(FLERR, cmd_ + ": set_state_code: code must be >= -3");
  double *slot = const_cast<double *>(owned_slot(spring));
  if (!slot) return false;
  hot_valid_ = false;  // the next step reloads the states from the records
  sp::SpringState st;
  st.unpack(slot + 1);
  st.code = code;
  st.pack(slot + 1);
  // The output row of this step reports the state at the end of the step, as Parmec's HISTORY 'SS' row
  // does: UNSPRING fires after the forces, and its row already shows the new code.
  const double id = static_cast<double>(defs_[spring].id);
  for (int r = 0; r < size_local_rows; r++)
    if (array_local[r][0] == id) array_local[r][6] = code;
  return true;
}

void FixParmecSpring::set_unspring_unload(int code, const sp::SpringTable *curve)
{
  if (code < 0) error->all(FLERR, cmd_ + ": set_unspring_unload: code must be >= 0");
  unspring_unload_[code] = curve;
}

static RegisterStyle reg_fix_parmec_spring("fix", "parmec/spring",
                                           "Parmec SPRING model: tables, dashpots, unload/ylim, offsets, friction",
                                           create_fix<FixParmecSpring>);

}  // namespace dembridge
