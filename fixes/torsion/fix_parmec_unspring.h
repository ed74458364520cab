// fix parmec/unspring: LAMMPS glue for Parmec's UNSPRING rule (issue 7 deliverable 2; kernels
// UnspringRule/UnspringTest in this folder, doc/parmec_torsion_kernels.md §5; user page
// doc/fix_parmec_torsion.md "fix parmec/unspring"). Drives the springs of one fix parmec/spring through
// its public API (doc/fix_parmec_spring.md "API for UNSPRING").
//
// Design: the rules (kernel UnspringRule, spring IDs = the user spring IDs of the spring fix) and the
// TSERIES are constant and replicated on every rank. The evolving data are global: the counter of each
// rule (nfreq, decremented by failed tests) and the step the run started from; they go into the global
// restart data. After every step (end_of_step, after all spring forces) every rank gathers the tested
// entity of all springs (collective, the owners' values summed with zeros: exact), runs unspring_test
// identically, and applies the new state codes to the springs it owns: they act from the next step.
#pragma once

#include "fix.h"

#include "definition_reader.h"

#include "time_series.h"
#include "unspring_rule.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dembridge {

class FixParmecSpring;

class FixParmecUnspring : public LAMMPS_NS::Fix {
 public:
  FixParmecUnspring(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixParmecUnspring() override;
  int setmask() override;
  void init() override;
  void end_of_step() override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;
  double compute_vector(int n) override;

 private:
  std::string cmd_;
  state::DefinitionReader reader_;
  std::string spring_fix_id_;
  // Unload curves, registered with the spring fix by pointer: kept alive until the program ends (a
  // static list), so the spring fix may outlive this fix (unfix) without dangling pointers.
  std::shared_ptr<std::map<int, springs::TimeSeries>> tseries_;
  std::vector<torsion::UnspringRule> rules_;
  std::vector<int> remaining_;     // per rule: counter (nfreq initially, 0 = fired)
  std::vector<double> last_value_; // per rule: combined value of the last test
  std::vector<double> fired_at_;   // per rule: kernel step of the trigger, -1 if not fired
  bool registered_ = false;        // input effects applied (first init, or restored from a restart)
  LAMMPS_NS::bigint start_ = 0;    // LAMMPS step before the first force evaluation (kernel step 0)

  FixParmecSpring *springs();
  // 'tseries' and 'rule' (the keyword loop and 'file' are the state layer's DefinitionReader)
  bool parse_definition(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
};

}  // namespace dembridge
