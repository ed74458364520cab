#include "global_property.h"
#include "math/number_word.h"

#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace dembridge::property {

namespace {

const char *const kUsage =
    "fix property/global: expected 'NAME scalar|vector|peratomtype|atomtype|matrix|peratomtypepair|atomtypepair values...'";

double parse_number(const std::string &word, const std::string &name, int index)
{
  double v;
  if (!math::read_number(word, v))
    throw PropertyError("fix property/global " + name + ": value " + std::to_string(index) + " '" + word +
                        "' is not a finite number");
  return v;
}

Style parse_style(const std::string &w)
{
  if (w == "scalar") return Style::Scalar;
  if (w == "vector") return Style::Vector;
  if (w == "peratomtype" || w == "atomtype") return Style::PerAtomType;
  if (w == "matrix") return Style::Matrix;
  if (w == "peratomtypepair" || w == "atomtypepair") return Style::PerAtomTypePair;
  throw PropertyError("fix property/global: unknown style '" + w +
                      "'. Valid styles are scalar, vector, atomtype/peratomtype, matrix, or atomtypepair/peratomtypepair");
}

}  // namespace

const char *kind_name(Kind k)
{
  switch (k) {
    case Kind::Scalar: return "scalar";
    case Kind::PerType: return "peratomtype";
    case Kind::PerTypePair: return "peratomtypepair";
  }
  return "?";
}

Kind GlobalProperty::kind() const
{
  switch (style_) {
    case Style::Scalar: return Kind::Scalar;
    case Style::Vector:
    case Style::PerAtomType: return Kind::PerType;
    default: return Kind::PerTypePair;
  }
}

GlobalProperty GlobalProperty::parse(const std::vector<std::string> &args)
{
  // LIGGGHTS: fewer than 6 words in the fix command (NAME STYLE value) is an error.
  if (args.size() < 3) throw PropertyError(std::string("fix property/global: not enough arguments; ") + kUsage);
  GlobalProperty p;
  p.name_ = args[0];
  p.style_ = parse_style(args[1]);
  std::size_t first = 2;
  if (p.style_ == Style::Matrix || p.style_ == Style::PerAtomTypePair) {
    const std::string &w = args[2];
    long long n = 0;
    if (!math::read_integer(w, n) || n < 1 || n > INT_MAX)
      throw PropertyError("fix property/global " + p.name_ + ": " + args[1] +
                          " expects the number of columns as a positive integer first, got '" + w + "'");
    p.ncols_ = int(n);
    first = 3;
    if (args.size() == first)
      throw PropertyError("fix property/global " + p.name_ + ": " + args[1] + " " + w + " has no values");
  }
  for (std::size_t k = first; k < args.size(); ++k)
    p.values_.push_back(parse_number(args[k], p.name_, int(k - first + 1)));

  const int nvalues = int(p.values_.size());
  if (p.style_ == Style::Scalar && nvalues != 1)
    throw PropertyError("fix property/global " + p.name_ + ": scalar expects exactly 1 value, got " + std::to_string(nvalues));
  if (p.style_ == Style::Matrix || p.style_ == Style::PerAtomTypePair) {
    if (nvalues % p.ncols_ != 0)
      throw PropertyError("fix property/global " + p.name_ + ": " + std::to_string(nvalues) + " values given for " +
                          std::to_string(p.ncols_) + " columns; the number of values must be a multiple of the number of columns");
    if (p.style_ == Style::PerAtomTypePair) {
      if (nvalues != p.ncols_ * p.ncols_)
        throw PropertyError("fix property/global " + p.name_ + ": per-atomtype property matrix must be symmetric, i.e. N atom types "
                            "require you to define N columns and N rows with N*N total values (got " + std::to_string(p.ncols_) +
                            " columns and " + std::to_string(nvalues) + " values)");
      for (int r = 0; r < p.ncols_; ++r)
        for (int c = r + 1; c < p.ncols_; ++c)
          if (p.values_[r * p.ncols_ + c] != p.values_[c * p.ncols_ + r])
            throw PropertyError("fix property/global " + p.name_ + ": per-atomtype property matrix must be symmetric, but the value for types (" +
                                std::to_string(r + 1) + "," + std::to_string(c + 1) + ") differs from (" + std::to_string(c + 1) + "," +
                                std::to_string(r + 1) + ")");
    }
  }
  return p;
}

GlobalProperty GlobalProperty::from_parts(const std::string &name, Style style, int ncols, const std::vector<double> &values)
{
  static const char *words[] = {"scalar", "vector", "peratomtype", "matrix", "peratomtypepair"};
  std::vector<std::string> args{name, words[int(style)]};
  if (style == Style::Matrix || style == Style::PerAtomTypePair) args.push_back(std::to_string(ncols));
  char buf[32];
  for (double v : values) {
    std::snprintf(buf, sizeof buf, "%.17g", v);
    args.emplace_back(buf);
  }
  return parse(args);
}

void GlobalProperty::require(Kind want, int max_type, const std::string &caller) const
{
  if (kind() != want)
    throw PropertyError(std::string(kind_name(want)) + " style required for fix property/global variable " + name_ +
                        " for usage with " + caller + " (it was defined as " + kind_name(kind()) + ")");
  if (want == Kind::PerType && int(values_.size()) < max_type)
    throw PropertyError("Length not sufficient for variable " + name_ + " for usage with " + caller + ": " +
                        std::to_string(values_.size()) + " values for atom types up to " + std::to_string(max_type));
  if (want == Kind::PerTypePair && (ncols_ < max_type || nrows() < max_type))
    throw PropertyError("Length not sufficient for variable " + name_ + " for usage with " + caller + ": a " +
                        std::to_string(nrows()) + "x" + std::to_string(ncols_) + " matrix for atom types up to " +
                        std::to_string(max_type));
}

std::string missing_property_message(const std::string &name, const std::string &caller)
{
  return "Could not locate a fix/property storing value(s) for " + name + " as requested by " + caller +
         ". Define it with 'fix ID all property/global " + name + " ...'";
}

}  // namespace dembridge::property
