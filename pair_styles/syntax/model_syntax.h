// The three pair_style dialects (LIGGGHTS 2.x names + keywords, LIGGGHTS 3.x `gran model ...`,
// LAMMPS numeric `Kn Kt gamman gammat xmu dampflag`) parsed into one ModelDescription.
// LAMMPS-free; throws SyntaxError with a message naming the argument and what was expected.
#pragma once

#include "contact_config.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace dembridge::gran {

struct SyntaxError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class Dialect { Liggghts2x, Liggghts3x, LammpsNumeric };

struct LammpsNumericCoeffs {  // LAMMPS built-in gran/* arguments
  double kn = 0, kt = 0, gamman = 0, gammat = 0, xmu = 0;
  int dampflag = 1;
  bool limit_damping = false;
};

struct ModelDescription {
  std::string style;  // as written by the user, e.g. "gran/hooke"
  Dialect dialect = Dialect::Liggghts2x;
  ContactConfig contact;  // the sub-models and semantics switches
  bool sanity_checks = true;
  bool force_on = true;
  LammpsNumericCoeffs numeric;
  std::vector<std::string> warnings;  // accepted-but-ignored input the user should hear about

  // The name LIGGGHTS uses as "CALLER" in property messages.
  std::string caller() const { return style; }
};

// style: the pair style name (e.g. "gran/hooke", "gran"); args: the words after it.
ModelDescription parse_pair_style(const std::string &style, const std::vector<std::string> &args);

// True if the style name is one this module handles.
bool is_gran_style(const std::string &style);

}  // namespace dembridge::gran
