#include "command_args.h"

#include "error.h"
#include "input.h"
#include "variable.h"

#include <cmath>
#include <cstdlib>

namespace dembridge {

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
  char *end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !std::isfinite(v)) fail(what, "expected a finite number, got '" + s + "'");
  return v;
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
  char *end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0') fail(what, "expected an integer, got '" + s + "'");
  return int(v);
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

bool CommandArgs::yes_no(const std::string &what)
{
  const std::string s = next(what);
  if (s != "yes" && s != "no") fail(what, "expected 'yes' or 'no', got '" + s + "'");
  return s == "yes";
}

bool CommandArgs::on_off(const std::string &what)
{
  const std::string s = next(what);
  if (s != "on" && s != "off") fail(what, "expected 'on' or 'off', got '" + s + "'");
  return s == "on";
}

std::string CommandArgs::variable_name(const std::string &what)
{
  const std::string s = next(what);
  if (s.rfind("v_", 0) != 0 || s.size() < 3) fail(what, "expected an equal-style variable as v_name, got '" + s + "'");
  return s.substr(2);
}

}  // namespace dembridge
