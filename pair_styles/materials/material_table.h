// Per-type-pair coefficient table of a contact model, built once per init() from the global
// properties (spec granular-models §3, §4, §10). LAMMPS-free; throws MaterialError.
#pragma once

#include "global_property.h"
#include "model_syntax.h"
#include "pair_coeffs.h"

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dembridge::gran {

struct MaterialError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class UnitSystem { SI, CGS, LJ };

// Finds a property by name (nullptr if none is defined).
using PropertyLookup = std::function<const property::GlobalProperty *(const std::string &name)>;

class MaterialTable {
 public:
  MaterialTable() = default;
  // max_type: the largest atom type present; types are 1..max_type.
  // nktv2p: LAMMPS force conversion; the numeric dialect divides Kn, Kt by it as the built-ins do.
  static MaterialTable build(const ModelDescription &model, const PropertyLookup &lookup, int max_type, UnitSystem units,
                             double nktv2p = 1.0);

  int max_type() const { return max_type_; }
  const PairCoeffs &at(int itype, int jtype) const { return table_[itype * (max_type_ + 1) + jtype]; }
  // Whether every type pair has the same coefficients, bit for bit (one atom type, or equal
  // materials): the pair loop then broadcasts them instead of looking them up per pair.
  bool uniform() const;
  // The names of the properties this model read (for restart bookkeeping and messages).
  const std::vector<std::string> &used_properties() const { return used_; }

 private:
  int max_type_ = 0;
  std::vector<PairCoeffs> table_;  // (max_type+1)^2, row/column 0 unused
  std::vector<std::string> used_;
};

}  // namespace dembridge::gran
