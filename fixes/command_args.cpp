#include "command_args.h"
#include "math/number_word.h"

#include "error.h"
#include "input.h"
#include "utils.h"
#include "variable.h"

#include <climits>
#include <cmath>
#include <cstdlib>

namespace dembridge {

namespace args {

bool is_number(const std::string &word) { return LAMMPS_NS::utils::is_double(word); }

std::optional<double> number(LAMMPS_NS::LAMMPS *lmp, const std::string &word)
{
  double finite;  // utils::numeric stops with its own ERROR on an out-of-range word (1e400): tested first
  if (!LAMMPS_NS::utils::is_double(word) || !math::read_number(word, finite)) return std::nullopt;
  return LAMMPS_NS::utils::numeric(FLERR, word, false, lmp);
}

std::optional<long long> integer(LAMMPS_NS::LAMMPS *lmp, const std::string &word)
{
  if (!LAMMPS_NS::utils::is_integer(word)) return std::nullopt;
  const std::string digits = word.substr(word[0] == '+' || word[0] == '-' ? 1 : 0);
  if (digits.size() > 18 && digits.find_first_not_of('0') < digits.size() - 18) return std::nullopt;  // beyond bigint
  return static_cast<long long>(LAMMPS_NS::utils::bnumeric(FLERR, word, false, lmp));
}

bool parse_double(LAMMPS_NS::LAMMPS *lmp, const std::string &word, double &v)
{
  const std::optional<double> d = number(lmp, word);
  if (d) v = *d;
  return d.has_value();
}

bool parse_long(LAMMPS_NS::LAMMPS *lmp, const std::string &word, long &v)
{
  const std::optional<long long> n = integer(lmp, word);
  if (n) v = long(*n);
  return n.has_value();
}

}  // namespace args

void CommandArgs::fail(const std::string &what, const std::string &expected)
{
  error->all(FLERR, cmd_ + ": " + what + ": " + expected);
  std::abort();  // not reached: error->all throws or exits
}

const char *CommandArgs::next(const std::string &what)
{
  if (i_ >= narg_) fail(what, "missing value at the end of the command");
  return arg_[i_++];
}

void CommandArgs::expect_keyword(const std::string &kw, const std::string &usage)
{
  if (i_ >= narg_) fail("'" + kw + "'", "missing (expected " + usage + ")");
  const std::string got = arg_[i_++];
  if (got != kw) fail("'" + got + "'", "expected keyword '" + kw + "' here (" + usage + ")");
}

std::string CommandArgs::word(const std::string &what) { return next(what); }

double CommandArgs::number(const std::string &what)
{
  const std::string s = next(what);
  const std::optional<double> v = args::number(lmp, s);
  if (!v) fail(what, "expected a finite number, got '" + s + "'");
  return *v;
}

double CommandArgs::positive(const std::string &what)
{
  const double v = number(what);
  if (!(v > 0.0)) fail(what, "expected a positive number, got " + std::string(arg_[i_ - 1]));
  return v;
}

int CommandArgs::integer(const std::string &what)
{
  const std::string s = next(what);
  const std::optional<long long> v = args::integer(lmp, s);
  if (!v || *v > INT_MAX || *v < INT_MIN) fail(what, "expected an integer, got '" + s + "'");
  return int(*v);
}

math::Vec3 CommandArgs::vec3(const std::string &what)
{
  math::Vec3 v;
  for (int k = 0; k < 3; ++k) v[k] = number(what + " (component " + std::to_string(k + 1) + " of 3)");
  return v;
}

math::Vec3 CommandArgs::nonzero_vec3(const std::string &what)
{
  const math::Vec3 v = vec3(what);
  if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0) fail(what, "expected a non-zero vector, got 0 0 0");
  return v;
}

// Only the pair named (LIGGGHTS's syntax), read by utils::logical
bool CommandArgs::yes_no(const std::string &what)
{
  const std::string s = next(what);
  if (s != "yes" && s != "no") fail(what, "expected 'yes' or 'no', got '" + s + "'");
  return LAMMPS_NS::utils::logical(FLERR, s, false, lmp) == 1;
}

bool CommandArgs::on_off(const std::string &what)
{
  const std::string s = next(what);
  if (s != "on" && s != "off") fail(what, "expected 'on' or 'off', got '" + s + "'");
  return LAMMPS_NS::utils::logical(FLERR, s, false, lmp) == 1;
}

std::string CommandArgs::variable_name(const std::string &what)
{
  const std::string s = next(what);
  if (s.rfind("v_", 0) != 0 || s.size() < 3) fail(what, "expected an equal-style variable as v_name, got '" + s + "'");
  return s.substr(2);
}

}  // namespace dembridge
