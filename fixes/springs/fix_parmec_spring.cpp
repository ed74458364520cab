// fix parmec/spring: LAMMPS glue for the Parmec SPRING kernels. See fix_parmec_spring.h for the design
// and doc/fix_parmec_spring.md for the user syntax.
#include "fix_parmec_spring.h"
#include "command_args.h"
#include "fix_parmec_spring_slot.h"
#include "definition_file.h"

#include "serial_fix_note.h"
#include "lammps_compat.h"
#include "style_registry.h"
#include "container_bytes.h"

#include "math/quaternion.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "compute.h"
#include "modify.h"
#include "update.h"
#include "utils.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;
namespace sp = dembridge::springs;

namespace dembridge {

using namespace spring_fix;

namespace {

const char *const kSpringOptions[] = {"dashpot", "ratio",  "direction", "planar", "plane", "unload",
                                      "ylim",    "inactive", "offset",  "friction", "kskn"};

bool is_spring_option(const std::string &s)
{
  for (const char *o : kSpringOptions)
    if (s == o) return true;
  return false;
}

using args::is_number;
using Rot = sp::BodyRotation;

}  // namespace

FixParmecSpring::FixParmecSpring(LAMMPS *lmp, int narg, char **arg) :
    PerAtomStateFix(lmp, narg, arg, kSlot),
    reader_(lmp, cmd_, state::DefinitionReader::kTable | state::DefinitionReader::kTseries |
                           state::DefinitionReader::kFile | state::DefinitionReader::kHistory |
                           state::DefinitionReader::kStart,
            "spring", "table, tseries, spring, file, history, start, eqm, critical, inertia, order or loops"),
    inertia_(lmp, cmd_)
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
                  if (tok[i] == "critical") {  // CRITICAL in Parmec's operation order and literals
                    critical_parmec_ = reader_.choice(tok, i, where, {"lammps", "parmec"}) == 1;
                    return true;
                  }
                  if (tok[i] == "inertia") {  // CRITICAL with the bodies' inertia tensors (Parmec front end)
                    if (i + 1 >= tok.size())
                      error->all(FLERR, cmd_ + ": inertia: expected the name of a d2_NAME 6 per-atom property");
                    inertia_.set_name(tok[i + 1]);
                    i += 2;
                    return true;
                  }
                  if (tok[i] == "order") {
                    parmec_order_ = reader_.choice(tok, i, where, {"lammps", "parmec"}) == 1;
                    return true;
                  }
                  if (tok[i] == "loops") {  // 'general': no loop per spring kind (a check of those loops)
                    general_loops_ = reader_.choice(tok, i, where, {"kinds", "general"}) == 1;
                    report_loops_ = true;
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
      dembridge::minimum_image(domain, FLERR, v[0], v[1], v[2]);
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

// Springs of any length: the layer's setup_pre_exchange() raised the ghost cutoff above the longest spring, and
// its pre_exchange() keeps it above them at every re-neighbouring (part2 is then always a ghost of part1's owner).
void FixParmecSpring::setup(int)
{
  evaluate(Mode::Setup);
  warn_beyond_critical();
  if (report_loops_) {  // 'loops' given: which loop takes how many springs in the committed steps
    const bool kinds = !general_loops_ && !parmec_order_;
    long mine[3] = {kinds ? long(centre_r_.size()) : 0, kinds ? long(plane_r_.size()) : 0,
                    kinds ? long(other_r_.size()) : long(plan_.size())};
    long all[3] = {0, 0, 0};
    MPI_Allreduce(mine, all, 3, MPI_LONG, MPI_SUM, world);
    if (comm->me == 0)
      utils::logmesg(lmp, "{}: springs per loop: centre {}, plane {}, general {}\n", cmd_, all[0], all[1], all[2]);
  }
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
  note_serial_fixes(lmp, cmd_);  // fixes left on one thread (no 'suffix omp'), fixes/integrate/serial_fix_note.h
  threads_used_ = 0;
}

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

double FixParmecSpring::memory_usage()
{
  return PerAtomStateFix::memory_usage() + where_.bytes() + incidence_.bytes() +
      state::containers_bytes(names_, spring_ids_, defs_, parmec_rank_, unspring_unload_, id_index_, plan_, ghost_r_, hot_,
                              first_, results_, failure_text_, inc_key_, inc_atom1_, inc_atom2_, torque_free_, centre_r_,
                              plane_r_, other_r_, all_r_, atom_rot_, crit_table_);
}

static RegisterStyle reg_fix_parmec_spring("fix", "parmec/spring",
                                           "Parmec SPRING model: tables, dashpots, unload/ylim, offsets, friction",
                                           create_fix<FixParmecSpring>);

}  // namespace dembridge
