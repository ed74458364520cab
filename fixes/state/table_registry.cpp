#include "table_registry.h"

#include <cstdlib>
#include <stdexcept>

namespace dembridge::state {

bool parse_double(const std::string &s, double &v)
{
  if (s.empty()) return false;
  char *end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}

bool is_number(const std::string &s)
{
  double v;
  return parse_double(s, v);
}

bool parse_long(const std::string &s, long &v)
{
  if (s.empty()) return false;
  char *end = nullptr;
  v = std::strtol(s.c_str(), &end, 10);
  return *end == '\0';
}

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
