// Argument reader of the plugin's commands, on top of LAMMPS's own (`Pointers`, `Error`, `utils`): a cursor over
// arg[first..narg) whose every failure is a LAMMPS ERROR naming the command, the argument and what was
// expected ("fix ID: fraction_hertz: expected a positive number, got -1"); and the word readers under it, for
// the commands that parse their words themselves (definition files, key-value lists).
#pragma once

#include "pointers.h"
#include "math/vec3.h"

#include <optional>
#include <string>

namespace dembridge {

// One word read through LAMMPS's utils: a number as utils::is_double accepts it and utils::numeric converts
// it (finite), an integer as utils::is_integer and utils::bnumeric. Empty where the word is not one, for the
// caller's ERROR, which names the command, the argument and what was expected (utils's own names neither).
namespace args {
bool is_number(const std::string &word);  // utils::is_double
std::optional<double> number(LAMMPS_NS::LAMMPS *lmp, const std::string &word);
std::optional<long long> integer(LAMMPS_NS::LAMMPS *lmp, const std::string &word);
// The same as a bool with the value out, for the readers that test and read in one go.
bool parse_double(LAMMPS_NS::LAMMPS *lmp, const std::string &word, double &v);
bool parse_long(LAMMPS_NS::LAMMPS *lmp, const std::string &word, long &v);
}  // namespace args

class CommandArgs : protected LAMMPS_NS::Pointers {
 public:
  CommandArgs(LAMMPS_NS::LAMMPS *lmp, std::string cmd, int narg, char **arg, int first)
      : Pointers(lmp), cmd_(std::move(cmd)), narg_(narg), arg_(arg), i_(first)
  {
  }
  bool done() const { return i_ >= narg_; }
  int position() const { return i_; }
  const char *peek() const { return i_ < narg_ ? arg_[i_] : ""; }

  [[noreturn]] void fail(const std::string &what, const std::string &expected);
  void expect_keyword(const std::string &kw, const std::string &usage);
  std::string word(const std::string &what);
  double number(const std::string &what);
  double positive(const std::string &what);
  int integer(const std::string &what);
  math::Vec3 vec3(const std::string &what);
  math::Vec3 nonzero_vec3(const std::string &what);
  bool yes_no(const std::string &what);
  bool on_off(const std::string &what);
  std::string variable_name(const std::string &what);  // v_name -> name (must be an equal-style variable)

 private:
  std::string cmd_;
  int narg_;
  char **arg_;
  int i_;
  const char *next(const std::string &what);
};

}  // namespace dembridge
