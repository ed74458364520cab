#include "table_registry.h"

#include <stdexcept>

namespace dembridge::state {

void TableRegistry::define_table(const std::string &id, const std::vector<double> &xy)
{
  if (tables_.count(id)) throw std::invalid_argument("ID defined twice");
  tables_.emplace(id, springs::SpringTable::from_pairs(xy, "values"));
}

void TableRegistry::define_tseries(const std::string &id, const std::vector<double> &tv)
{
  if (tseries_.count(id)) throw std::invalid_argument("ID defined twice");
  tseries_.emplace(id, tv.size() == 1 ? springs::TimeSeries::constant(tv[0]) : springs::TimeSeries::from_pairs(tv));
}

const springs::SpringTable *TableRegistry::table(const std::string &id) const
{
  auto it = tables_.find(id);
  return it == tables_.end() ? nullptr : &it->second;
}

const springs::TimeSeries *TableRegistry::tseries(const std::string &id) const
{
  auto it = tseries_.find(id);
  return it == tseries_.end() ? nullptr : &it->second;
}

}  // namespace dembridge::state
