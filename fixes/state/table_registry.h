// Named tables and TSERIES of a Parmec-style fix: `table ID x1 y1 x2 y2 ...`, `tseries ID t1 v1 ... | v`
// (LAMMPS-free; doc/per_atom_state.md). Entities refer to them by ID, forward references allowed; the
// registry owns them for the fix's lifetime (pointers stay valid: std::map never moves its nodes).
#pragma once

#include "spring_table.h"
#include "time_series.h"

#include <map>
#include <string>
#include <vector>

namespace dembridge::state {

class TableRegistry {
 public:
  // Throw std::invalid_argument: "ID defined twice", or the rule the values break.
  void define_table(const std::string &id, const std::vector<double> &xy);
  void define_tseries(const std::string &id, const std::vector<double> &tv);  // one value: a constant
  const springs::SpringTable *table(const std::string &id) const;             // null if not defined
  const springs::TimeSeries *tseries(const std::string &id) const;
  const std::map<std::string, springs::TimeSeries> &all_tseries() const { return tseries_; }

 private:
  std::map<std::string, springs::SpringTable> tables_;
  std::map<std::string, springs::TimeSeries> tseries_;
};

}  // namespace dembridge::state
