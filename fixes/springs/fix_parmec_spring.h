// fix parmec/spring: LAMMPS glue for the Parmec SPRING model (issue 5; kernels in this folder,
// doc/parmec_springs_kernels.md §5; user page doc/fix_parmec_spring.md).
//
// Design in one paragraph: the spring definitions (atom tags, reference geometry, law with pointers
// into this fix's table/TSERIES registry) are constant and replicated on every rank, indexed by the
// spring's position in the definition list. The evolving state of a spring (SpringState, 20 doubles,
// plus the force it applied in its last committed step) is a record of part1's atom in the per-atom
// state layer (fixes/state, doc/per_atom_state.md), which moves it with that atom (exchange, sort,
// restart). Each step the owner of part1 evaluates the spring with part2 as a local or ghost atom
// (closest image) and applies both forces; contributions to ghost atoms are summed back on their owners
// in spring order by the layer, so newton on/off and the decomposition do not matter.
//
// Files: fix_parmec_spring.cpp (definitions, reference geometry, set-up, restart), _evaluate.cpp (one evaluation:
// the loops on OpenMP threads, then each atom's sums in spring order), one file per loop (_general_loop.cpp,
// _centre_loop.cpp, _plane_loop.cpp; the step they share inline in _step.h), _parmec_order.cpp, _critical.cpp,
// _api.cpp (UNSPRING).
#pragma once

#include "body_inertia.h"
#include "definition_reader.h"
#include "local_incidence.h"
#include "per_atom_state_fix.h"

#include "math/quaternion.h"
#include "spring_geometry.h"
#include "spring_law.h"
#include "spring_state.h"
#include "spring_table.h"
#include "time_series.h"

#include <array>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace dembridge {

class FixParmecSpring : public state::PerAtomStateFix {
 public:
  FixParmecSpring(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  void init() override;
  void setup(int) override;
  // Out of line (not the base's inline one): the benchmark's callgrind figure collects this symbol.
  void post_force(int) override;
  void post_run() override;

  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

  // The layer's hook before it moves, packs or reads the records: the states advanced in hot_ are packed.
  void flush_records() override { sync_records(); }

  double compute_vector(int n) override;
  // CRITICAL lists: row r < spring_count(): spring r (definition order), row spring_count() + t - 1: atom
  // with tag t; columns h, omega, xi (h = DBL_MAX for an atom without springs)
  double compute_array(int i, int j) override;
  double memory_usage() override;  // the records (PerAtomStateFix) and the per-spring plan, states and results

  // Slot of one spring in its part1 atom's list: spring index, SpringState (20), last committed force
  // on part1 (3), flag "force valid" (1).
  static constexpr int kSlot = 1 + springs::SpringState::kPackedSize + 4;

  // ---- API for UNSPRING (fixes/torsion/ glue; doc/fix_parmec_spring.md "API for UNSPRING") ----------
  // Springs are numbered 0 .. spring_count()-1 in definition order (same on every rank).
  enum class Entity { Length, Stroke, F, SF, FF, SS, EQM };
  int spring_count() const { return static_cast<int>(defs_.size()); }
  int spring_index(long spring_id) const;   // -1 if no spring has this ID
  long spring_id(int spring) const { return defs_[spring].id; }
  // Values of the last evaluation. Local: NaN unless this rank owns the spring's state (owns part1).
  double entity_value(int spring, Entity e) const;
  // Collective: the entity of every spring (index = spring), summed over ranks.
  void gather_entity(Entity e, std::vector<double> &out);
  // Set the state code (SS) of a spring on the rank that owns it (no-op on the others, returns whether
  // it was set here): -3 regular, -2 UNSPRING-managed, -1 zero force, >= 0 unloaded with the curve
  // registered for that code by set_unspring_unload(). Takes effect at the next step; the SS column of
  // this step's output row shows it at once (the state at the end of the step, as Parmec reports it).
  bool set_state_code(int spring, int code);
  // Register the UNSPRING unload curve (strictly increasing, starting at 0) for state code >= 0. The
  // table is owned by the caller and must outlive the fix. A code without a curve removes the spring
  // at once (code -1), as Parmec's UNSPRING without an unload curve.
  void set_unspring_unload(int code, const springs::SpringTable *curve);

 private:
  // What every step reads comes first (flags, law, arms, normal, stroke0: three cache lines, not five of 360
  // bytes); the input as given and the reference centres after it.
  struct SpringDef {
    bool arm1_zero = true, arm2_zero = true;  // centre attachments (no moment arm), set by init()
    springs::DirectionMode mode = springs::DirectionMode::Follower;
    LAMMPS_NS::tagint tag2 = -1; // part2, -1: spatial anchor
    springs::SpringLaw law;
    // reference geometry (constructor, or restart file)
    springs::Vec3 arm1{};        // body-frame arm of point1 on part1
    springs::Vec3 arm2{};        // body-frame arm on part2, or the spatial anchor point if tag2 < 0
    springs::Vec3 nref{};        // Plane: normal in part2's body frame (or spatial if tag2 < 0)
    double stroke0 = 0.0;
    springs::Vec3 d{};           // unit direction (Constant/Planar)
    long id = 0;                 // user spring ID (output column 1)
    LAMMPS_NS::tagint tag1 = 0;  // part1
    bool centre1 = false, centre2 = false;  // point given as 'centre'
    bool inactive = false;
    springs::Vec3 P1{}, P2{};    // reference points as given (P2: point or plane point)
    springs::Vec3 normal{};      // unit plane normal as given (Plane)
    springs::Vec3 X1ref{}, X2ref{};  // reference centres (EQM with Parmec's Q8 arm)
  };

  // Names of the tables a spring refers to, resolved after all definitions are read.
  struct LawNames {
    std::string spring, dashpot, unload, offset;
  };
  state::DefinitionReader reader_;  // options, tables and TSERIES (owned for the fix's lifetime)
  std::vector<LawNames> names_;
  std::unordered_set<long> spring_ids_;
  std::vector<SpringDef> defs_;
  bool q8_arm_ = false;        // 'eqm parmec': ratio dashpots use Parmec's arm 2X - P (quirk Q8)
  // 'order parmec': Parmec's forces.ispc arithmetic (doc/fix_parmec_spring.md "Parmec's operation order"):
  // points from fix parmec/rigid's stored Λ, arms p - x, its relative velocity and (1/len)·w, and each atom's
  // contributions added run by run in Parmec's (part1, part2)-sorted spring order.
  bool parmec_order_ = false;
  // 'loops general': every spring through the general loop, none through the loops per kind (their results are
  // bitwise the general loop's; tests/python/test_parmec_spring_loops.py compares them)
  bool general_loops_ = false;
  bool report_loops_ = false;  // 'loops' given: setup logs the springs per loop
  LAMMPS_NS::Fix *rigid_ = nullptr;  // fix parmec/rigid: Λ per atom (local and ghost) as array_atom
  std::vector<long long> parmec_rank_;  // 2 per spring (part1, part2 side): flush event * nsprings + position
  void parmec_schedule();
  void add_in_parmec_order(int i, const state::LocalIncidence::Term *t0, const state::LocalIncidence::Term *t1,
                           double *f, double *torque) const;
  std::unordered_map<int, const springs::SpringTable *> unspring_unload_;
  mutable state::RecordIndex where_;  // spring index -> (local atom, record) of the states owned here
  std::unordered_map<long, int> id_index_;  // user spring ID -> spring index
  const double *owned_slot(int spring) const;

  // One evaluation: what every spring reads (set once per evaluate()).
  struct EvalContext {
    Mode mode = Mode::Commit;
    double dt = 0.0, tnow = 0.0;
    double **omega = nullptr, **quat = nullptr;
    double **rot = nullptr;  // 'order parmec': Λ row-major per atom (fix parmec/rigid)
    const springs::BodyRotation *body_rot = nullptr;  // the plane loop: each atom's matrix (null: per spring)
    const double *rmass = nullptr, *mass = nullptr, *radius = nullptr;
    double **inertia = nullptr;  // 'inertia NAME': d2_NAME per atom (local and ghost), else the sphere's
    const int *type = nullptr;
    const LAMMPS_NS::tagint *tag = nullptr;
    int nall = 0;           // local + ghost atoms
    bool periodic = false;  // part2's closest image looked up every step
    bool recheck = true;    // part2's index checked by tag (atoms re-indexed since the last evaluation, or periodic)
    bool fill = true;       // write the local output rows (something reads them this step)
  };
  enum class Failure { None, Part2Missing, Kernel };
  // What one spring gives its atoms (force, torque per side), written by the (threaded) evaluation and
  // contributed in spring order afterwards.
  struct SpringResult {
    // (F, a x F) on part1, then -(F, b x F) on part2: each side with its sign, so that the sums only add (the
    // negation is exact: adding -v is subtracting v)
    double ft[12];
    int i = 0, k = -1, key = 0;
    bool apply = false;
    Failure failure = Failure::None;
  };
  // What every evaluation index r reads before its spring's arithmetic (record, definition, atoms), kept
  // from step to step and rebuilt only when records move or atoms are added/removed (refresh_plan).
  struct PlanItem {
    double *slot = nullptr;
    const SpringDef *def = nullptr;
    int key = 0;  // spring index (def - defs_)
    int i = 0;   // local atom holding the record (part1)
    int k = -1;  // part2's local/ghost index found last time (checked by tag every step), -1: none yet
  };
  std::vector<PlanItem> plan_;
  unsigned long plan_generation_ = ~0ul;
  int plan_nlocal_ = -1, plan_nall_ = -1;
  bool incidence_current_ = false;  // incidence_ and ghost_r_ match plan_ (all springs applied)
  std::vector<int> ghost_r_;        // evaluation indices whose part2 is a ghost atom
  bool refresh_plan();
  // The states of plan_'s springs between steps (Commit evaluations advance them here, not in the records):
  // packed into the records only when something moves or reads the records, not every step.
  mutable std::vector<springs::SpringState> hot_;
  mutable bool hot_dirty_ = false;  // hot_ holds steps the records do not have yet
  bool hot_valid_ = false;          // hot_ matches plan_'s records
  void sync_records() const;
  std::vector<int> first_;             // first evaluation index of each local atom's records
  std::vector<SpringResult> results_;  // per evaluation index, reused from step to step
  std::unordered_map<int, std::string> failure_text_;  // kernel messages by spring index
  std::vector<int> inc_key_, inc_atom1_, inc_atom2_;    // per evaluation index: key, local atoms touched
  state::LocalIncidence incidence_;
  std::vector<char> torque_free_;  // per local atom: every spring's torque on it is a signed zero (built with incidence_)
  int threads_used_ = 0;  // most OpenMP threads of the spring loop in this run
  // Returns kMoved if part2's index differs from the plan's (the plan is updated), kFailed on a failure, kNear if
  // the atoms are farther apart than near_ (near the ghost cutoff: the layer checks their reach)
  enum : int { kMoved = 1, kFailed = 2, kNear = 4 };
  double near_ = 0.0;  // near_length() for this evaluation
  // Parmec: 'order parmec' (compiled once per mode, so that the default loop carries none of its branches).
  template <bool Parmec> int evaluate_spring(const EvalContext &ctx, int r);
  int evaluate_centres(const EvalContext &ctx, int r);  // committed centre-to-centre point spring, default order
  int evaluate_plane(const EvalContext &ctx, int r);    // committed plane carried by part2 from part1's centre
  // The loops (each in its own file), called by every thread of evaluate()'s parallel region: this thread's
  // share of the springs, OR of their flags. general_loop: rs[0..n).
  int centre_loop(const EvalContext &ctx);
  int plane_loop(const EvalContext &ctx);
  int general_loop(const EvalContext &ctx, const int *rs, int n);
  int part2_of(const EvalContext &ctx, PlanItem &item, SpringResult &res, int &flags);
  int commit_force(const EvalContext &ctx, int r, int k, const springs::SpringFrame &frame, const springs::Vec3 *arm2);
  springs::Vec3 law_step(const EvalContext &ctx, const SpringDef &d, int i, int k, const springs::SpringFrame &frame,
                         springs::SpringState &state, double &eqm) const;
  int output_row(const EvalContext &ctx, int r, const springs::SpringState &state, double eqm, int k);
  std::vector<int> centre_r_, plane_r_, other_r_;  // evaluation indices of evaluate_centres', evaluate_plane's, others'
  std::vector<int> all_r_;                         // 0 .. total-1 (every spring through the general loop)
  int centre_total_ = -1;                 // plan size the split was made for
  void split_plan(int total);
  std::vector<springs::BodyRotation> atom_rot_;  // per local/ghost atom, when the plane springs outnumber the atoms
  // The local output is written only on steps where something can read it (output_wanted()).
  bool readers_every_step_ = false;  // a compute reduce, fix ave/histo, python or external fix exists (init)
  bool output_wanted(Mode mode) const;
  LAMMPS_NS::bigint plan_builds_ = -1;  // neighbor->ncalls at the last evaluation (ghosts re-indexed since?)
  void record_failure(SpringResult &res, const char *what);
  [[noreturn]] void report_failure(const SpringResult &res);
  double spring_eqm(const EvalContext &c, const SpringDef &d, int i, int k, const springs::Vec3 &dir) const;
  double spring_eqm_general(const EvalContext &c, const SpringDef &d, int i, int k, const springs::Vec3 &dir) const;


  // parsing
  bool parse_spring(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
  void resolve();
  void reference_geometry(const std::vector<state::AtomSnapshot> &snap);
  void initial_states();

  void evaluate(Mode mode) override;
  void history_values(const double *rec, double *out) const override;
  void critical();
  void warn_beyond_critical();
  bool critical_parmec_ = false;  // 'critical parmec': CRITICAL rounded as Parmec's kernels round it  // WARNING at set-up when the timestep exceeds CRITICAL's estimate
  // The body inertia of CRITICAL and of the ratio dashpots' EQM ('inertia NAME', else the sphere's)
  state::BodyInertia inertia_;
  double crit_[2] = {0.0, 0.0};
  std::vector<double> crit_table_;  // 3 per row, see compute_array
  LAMMPS_NS::bigint crit_step_ = -1;
};

}  // namespace dembridge
