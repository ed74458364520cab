// fix parmec/torsion: LAMMPS glue for Parmec's TORSION_SPRING (issue 7; kernels in this folder,
// doc/parmec_torsion_kernels.md §5; user page doc/fix_parmec_torsion.md).
//
// Design (as fix parmec/spring): the spring definitions (atom tags, reference frame in part1's body frame,
// TorsionLaw with pointers into this fix's table registry) are constant and replicated on every rank,
// indexed by the spring's position in the definition list. The evolving TorsionState (16 doubles) plus
// the torque applied in the last committed step is a record of part1's atom in the per-atom state layer
// (fixes/state, doc/per_atom_state.md), which migrates/sorts/restarts it with that atom. Each step the owner of part1 evaluates the spring with part2 as a
// local or ghost atom and adds the torque to part1 and its opposite to part2; contributions to ghost
// atoms are reverse-communicated as (spring index, torque) lists and summed on the owner in spring
// order, so results do not depend on the decomposition.
#pragma once

#include "body_inertia.h"
#include "definition_reader.h"
#include "per_atom_state_fix.h"

#include "spring_table.h"
#include "torsion_frame.h"
#include "torsion_law.h"
#include "torsion_state.h"

#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace dembridge {

class FixParmecTorsion : public state::PerAtomStateFix {
 public:
  FixParmecTorsion(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  void init() override;
  void setup(int) override;

  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

  // Slot of one spring in its part1 atom's list: spring index, TorsionState (16), last committed torque
  // on part1 (3), flag "torque valid" (1).
  static constexpr int kSlot = 1 + torsion::TorsionState::kPackedSize + 4;

 private:
  struct TorsionDef {
    long id = 0;                  // user spring ID (output column 1)
    LAMMPS_NS::tagint tag1 = 0;   // part1
    LAMMPS_NS::tagint tag2 = -1;  // part2, -1: anchored in space
    torsion::TorsionFrame input;  // reference frame as given (spatial, at the fix command)
    torsion::TorsionFrame body;   // the same in part1's body frame (Λ1,0ᵀ applied)
    torsion::TorsionLaw law;
    double refpnt[3] = {0, 0, 0};
    bool has_refpnt = false;
  };
  struct LawNames {
    std::string k[3], d[3];
  };

  state::DefinitionReader reader_;  // options and tables (owned for the fix's lifetime)
  std::vector<TorsionDef> defs_;
  std::vector<LawNames> names_;
  std::unordered_set<long> ids_;
  bool parmec_order_ = false;        // 'order parmec': frames from fix parmec/rigid's stored Λ
  LAMMPS_NS::Fix *rigid_ = nullptr;  // fix parmec/rigid: Λ per atom (local and ghost) as array_atom
  state::BodyInertia inertia_;       // the critical-ratio dampers' body inertia ('inertia NAME', else the sphere's)


  bool parse_torsion(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
  void resolve();
  void reference_frames(const std::vector<state::AtomSnapshot> &snap);
  void initial_states();

  void evaluate(Mode mode) override;
  void history_values(const double *rec, double *out) const override;
};

}  // namespace dembridge
