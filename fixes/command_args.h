// Argument reader of the plugin's commands, on top of LAMMPS's own (`Pointers`, `Error`): a cursor over
// arg[first..narg) whose every failure is a LAMMPS ERROR naming the command, the argument and what was
// expected ("fix ID: fraction_hertz: expected a positive number, got -1").
#pragma once

#include "pointers.h"
#include "math/vec3.h"

#include <string>

namespace dembridge {

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
