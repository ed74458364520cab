// fix parmec/spring: LAMMPS glue for the Parmec SPRING model (issue 5; kernels in this folder,
// doc/parmec_springs_kernels.md §5; user page doc/fix_parmec_spring.md).
//
// Design in one paragraph: the spring definitions (atom tags, reference geometry, law with pointers
// into this fix's table/TSERIES registry) are constant and replicated on every rank, indexed by the
// spring's position in the definition list. The evolving state of a spring (SpringState, 20 doubles,
// plus the force it applied in its last committed step) lives in a per-atom list of part1's owner and
// migrates/restarts with that atom. Each step the owner of part1 evaluates the spring with part2 as a
// local or ghost atom (closest image) and applies both forces; contributions to ghost atoms are summed
// back with comm->reverse_comm(this), so newton on/off does not matter.
#pragma once

#include "fix.h"

#include "SpringGeometry.h"
#include "SpringLaw.h"
#include "SpringState.h"
#include "SpringTable.h"
#include "TimeSeries.h"

#include <map>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace dembridge {

class FixParmecSpring : public LAMMPS_NS::Fix {
 public:
  FixParmecSpring(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixParmecSpring() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
  void end_of_step() override;

  void grow_arrays(int nmax) override;
  void copy_arrays(int i, int j, int delflag) override;
  void set_arrays(int i) override;
  int pack_exchange(int i, double *buf) override;
  int unpack_exchange(int nlocal, double *buf) override;
  int pack_restart(int i, double *buf) override;
  void unpack_restart(int nlocal, int nth) override;
  int size_restart(int i) override;
  int maxsize_restart() override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

  double compute_vector(int n) override;
  int pack_reverse_comm(int n, int first, double *buf) override;
  void unpack_reverse_comm(int n, int *list, double *buf) override;
  double memory_usage() override;

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
  // registered for that code by set_unspring_unload(). Takes effect at the next step.
  bool set_state_code(int spring, int code);
  // Register the UNSPRING unload curve (strictly increasing, starting at 0) for state code >= 0. The
  // table is owned by the caller and must outlive the fix. A code without a curve removes the spring
  // at once (code -1), as Parmec's UNSPRING without an unload curve.
  void set_unspring_unload(int code, const springs::SpringTable *curve);

 private:
  struct SpringDef {
    long id = 0;                 // user spring ID (output column 1)
    LAMMPS_NS::tagint tag1 = 0;  // part1
    LAMMPS_NS::tagint tag2 = -1; // part2, -1: spatial anchor
    bool centre1 = false, centre2 = false;  // point given as 'centre'
    springs::Vec3 P1{}, P2{};    // reference points as given (P2: point or plane point)
    springs::DirectionMode mode = springs::DirectionMode::Follower;
    springs::Vec3 d{};           // unit direction (Constant/Planar)
    springs::Vec3 normal{};      // unit plane normal as given (Plane)
    bool inactive = false;
    springs::SpringLaw law;
    // reference geometry (constructor, or restart file)
    springs::Vec3 arm1{};        // body-frame arm of point1 on part1
    springs::Vec3 arm2{};        // body-frame arm on part2, or the spatial anchor point if tag2 < 0
    springs::Vec3 nref{};        // Plane: normal in part2's body frame (or spatial if tag2 < 0)
    double stroke0 = 0.0;
    springs::Vec3 X1ref{}, X2ref{};  // reference centres (EQM with Parmec's Q8 arm)
  };

  // Names of the tables a spring refers to, resolved after all definitions are read.
  struct LawNames {
    std::string spring, dashpot, unload, offset;
  };
  std::vector<LawNames> names_;
  std::unordered_set<long> spring_ids_;
  std::string cmd_;  // "fix ID parmec/spring" for messages
  std::map<std::string, springs::SpringTable> tables_;
  std::map<std::string, springs::TimeSeries> tseries_;
  std::vector<SpringDef> defs_;
  std::unordered_map<LAMMPS_NS::tagint, std::vector<int>> by_part1_;  // tag -> spring indices
  int max_per_atom_ = 0;
  bool has_pairs_ = false;     // some spring connects two atoms
  bool parmec_start_ = false;  // no spring force before the first committed step
  bool q8_arm_ = false;        // 'eqm parmec': ratio dashpots use Parmec's arm 2X - P (quirk Q8)
  std::unordered_map<int, const springs::SpringTable *> unspring_unload_;
  // spring index -> (local atom, slot) of the states owned here; rebuilt when atoms moved/sorted
  std::vector<std::pair<int, int>> where_;
  bool where_dirty_ = true;
  std::unordered_map<long, int> id_index_;  // user spring ID -> spring index
  const double *owned_slot(int spring) const;
  double spring_eqm(const SpringDef &d, int i, int k, const springs::Vec3 &dir, bool q8) const;
  bool geometry_from_restart_ = false;
  double cutghost_ = 0.0;

  std::vector<std::vector<double>> slots_;  // per atom
  // Per atom (local and ghost) up to kmax_ contributions [spring index, force(3), torque(3)], summed
  // on the owner in spring order after the reverse communication (decomposition-independent sums).
  static constexpr int kMaxOrdered = 64;
  int kmax_ = 1;
  bool ordered_ = true;
  std::vector<int> ccount_;
  std::vector<double> cbuf_;
  int nmax_ = 0;
  int nlocal_rows_ = 0;
  int maxlocal_ = 0;

  // parsing
  void parse(std::vector<std::string> tok, const std::string &where);
  void parse_spring(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
  double number(const std::string &s, const std::string &what, const std::string &where);
  void read_file(const std::string &path);
  void resolve();
  void reference_geometry();
  void initial_states();

  enum class Mode { Commit, Trial, Setup };
  void evaluate(Mode mode);
  void grow_local(int n);
  // 'history FILE N SPRID ...': CSV of chosen springs every N steps (rank 0 writes)
  std::string hist_file_;
  int hist_every_ = 0;
  std::vector<long> hist_ids_;
  std::unordered_map<int, int> hist_pos_;  // spring index -> column group
  FILE *hist_fp_ = nullptr;
  void critical();
  double crit_[2] = {0.0, 0.0};
  LAMMPS_NS::bigint crit_step_ = -1;
  void contribute(int i, int idx, const springs::Vec3 &F, const springs::Vec3 &T, double sign);
};

}  // namespace dembridge
