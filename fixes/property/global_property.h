// LIGGGHTS-compatible global property (spec granular-models §3): parsing, validation, typed access.
// LAMMPS-free: the fix glue turns PropertyError into a LAMMPS ERROR.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace dembridge::property {

struct PropertyError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The style word the user wrote; vector == peratomtype and matrix == peratomtypepair as data kinds,
// but only the *pair styles of atom types* must be square and symmetric.
enum class Style { Scalar, Vector, PerAtomType, Matrix, PerAtomTypePair };
enum class Kind { Scalar, PerType, PerTypePair };

const char *kind_name(Kind k);  // "scalar", "peratomtype", "peratomtypepair"

class GlobalProperty {
 public:
  // args: the words after "fix ID group property/global", i.e. NAME STYLE [ncols] values...
  static GlobalProperty parse(const std::vector<std::string> &args);

  // Rebuilds a property from its stored parts (restart files); validates like parse().
  static GlobalProperty from_parts(const std::string &name, Style style, int ncols, const std::vector<double> &values);

  const std::string &name() const { return name_; }
  Style style() const { return style_; }
  Kind kind() const;
  int ncols() const { return ncols_; }
  int nrows() const { return ncols_ > 0 ? int(values_.size()) / ncols_ : 0; }
  const std::vector<double> &values() const { return values_; }

  double scalar() const { return values_[0]; }
  double per_type(int type) const { return values_[type - 1]; }  // 1-based types
  double per_type_pair(int itype, int jtype) const { return values_[(itype - 1) * ncols_ + (jtype - 1)]; }

  // Checks that this property can serve `caller` as `kind` for atom types 1..max_type
  // (2.x length rule: at least max_type values / a max_type x max_type block; extras are ignored).
  void require(Kind kind, int max_type, const std::string &caller) const;

  bool same_values(const GlobalProperty &o) const { return style_ == o.style_ && ncols_ == o.ncols_ && values_ == o.values_; }

 private:
  std::string name_;
  Style style_ = Style::Scalar;
  int ncols_ = 1;
  std::vector<double> values_;
};

// Message of a missing property, shared by every caller.
std::string missing_property_message(const std::string &name, const std::string &caller);

}  // namespace dembridge::property
