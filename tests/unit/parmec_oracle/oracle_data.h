// Reading the Parmec oracle (tests/data/parmec-kernels): CSV histories (plain or .gz) and meta.json numbers.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace oracle {

std::string dir(const std::string& relative);  // DEMBRIDGE_PARMEC_ORACLE_DIR + "/" + relative

// Column-major CSV: header names, one double per cell. Tries `path`, then `path + ".gz"`.
struct History {
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> cols;
  const std::vector<double>& operator[](const std::string& name) const;
  std::size_t rows() const { return cols.empty() ? 0 : cols.begin()->second.size(); }
};
History read_history(const std::string& path);

// Flat numbers of a meta.json key (first occurrence; nested arrays flattened; NaN/Infinity understood).
std::vector<double> meta_numbers(const std::string& json_path, const std::string& key);
double meta_number(const std::string& json_path, const std::string& key);

}  // namespace oracle
