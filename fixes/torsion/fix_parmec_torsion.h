// fix parmec/torsion: LAMMPS glue for Parmec's TORSION_SPRING (issue 7; kernels in this folder,
// doc/parmec_torsion_kernels.md §5; user page doc/fix_parmec_torsion.md).
//
// Design (as fix parmec/spring): the spring definitions (atom tags, reference frame in part1's body frame,
// TorsionLaw with pointers into this fix's table registry) are constant and replicated on every rank,
// indexed by the spring's position in the definition list. The evolving TorsionState (16 doubles) plus
// the torque applied in the last committed step lives in a per-atom list of part1's owner and
// migrates/restarts with that atom. Each step the owner of part1 evaluates the spring with part2 as a
// local or ghost atom and adds the torque to part1 and its opposite to part2; contributions to ghost
// atoms are reverse-communicated as (spring index, torque) lists and summed on the owner in spring
// order, so results do not depend on the decomposition.
#pragma once

#include "fix.h"

#include "SpringTable.h"
#include "TorsionFrame.h"
#include "TorsionLaw.h"
#include "TorsionState.h"

#include <map>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace dembridge {

class FixParmecTorsion : public LAMMPS_NS::Fix {
 public:
  FixParmecTorsion(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixParmecTorsion() override;
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

  int pack_reverse_comm(int n, int first, double *buf) override;
  void unpack_reverse_comm(int n, int *list, double *buf) override;
  double memory_usage() override;

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

  std::string cmd_;  // "fix ID parmec/torsion" for messages
  std::map<std::string, springs::SpringTable> tables_;
  std::vector<TorsionDef> defs_;
  std::vector<LawNames> names_;
  std::unordered_set<long> ids_;
  std::unordered_map<LAMMPS_NS::tagint, std::vector<int>> by_part1_;
  int max_per_atom_ = 0;
  bool has_pairs_ = false;
  bool parmec_start_ = false;

  std::vector<std::vector<double>> slots_;  // per atom
  static constexpr int kMaxOrdered = 64;
  int kmax_ = 1;
  bool ordered_ = true;
  std::vector<int> ccount_;
  std::vector<double> cbuf_;  // per atom kmax_ entries [spring index, torque(3)]
  int maxlocal_ = 0;

  // history
  std::string hist_file_;
  int hist_every_ = 0;
  std::vector<long> hist_ids_;
  std::unordered_map<int, int> hist_pos_;
  FILE *hist_fp_ = nullptr;

  void parse(const std::vector<std::string> &tok, const std::string &where);
  void parse_torsion(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
  double number(const std::string &s, const std::string &what, const std::string &where);
  void read_file(const std::string &path);
  void reference_frames();
  void initial_states();

  enum class Mode { Commit, Trial, Setup };
  void evaluate(Mode mode);
  void grow_local(int n);
  void contribute(int i, int idx, const double *t, double sign);
};

}  // namespace dembridge
