// A number read from one word of a command, for the LAMMPS-free parsers (wall, pair-style, insertion and
// property syntax): the grammar of LAMMPS's utils::is_double and utils::is_integer (an optional sign, digits
// with at most one '.', an optional exponent; no inf, nan, hex or blanks), so a word reads the same here as in
// the LAMMPS glue, which reads through utils itself (fixes/command_args.h). The value is strtod's, as atof's.
#pragma once

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

namespace dembridge::math {

// utils::is_double's grammar
inline bool is_number_word(const std::string &w)
{
  std::size_t k = (!w.empty() && (w[0] == '+' || w[0] == '-')) ? 1 : 0;
  int digits = 0, dots = 0;
  for (; k < w.size() && (std::isdigit(static_cast<unsigned char>(w[k])) || w[k] == '.'); ++k)
    (w[k] == '.' ? dots : digits)++;
  if (digits == 0 || dots > 1) return false;
  if (k == w.size()) return true;
  if (w[k] != 'e' && w[k] != 'E') return false;
  if (++k < w.size() && (w[k] == '+' || w[k] == '-')) ++k;
  const std::size_t first = k;
  while (k < w.size() && std::isdigit(static_cast<unsigned char>(w[k]))) ++k;
  return k > first && k == w.size();
}

// utils::is_integer's grammar
inline bool is_integer_word(const std::string &w)
{
  std::size_t k = (!w.empty() && (w[0] == '+' || w[0] == '-')) ? 1 : 0;
  if (k == w.size()) return false;
  for (; k < w.size(); ++k)
    if (!std::isdigit(static_cast<unsigned char>(w[k]))) return false;
  return true;
}

// A finite number, else false (v untouched)
inline bool read_number(const std::string &w, double &v)
{
  if (!is_number_word(w)) return false;
  const double d = std::strtod(w.c_str(), nullptr);
  if (!std::isfinite(d)) return false;
  v = d;
  return true;
}

// An integer that fits a long long, else false (v untouched)
inline bool read_integer(const std::string &w, long long &v)
{
  if (!is_integer_word(w)) return false;
  errno = 0;
  const long long n = std::strtoll(w.c_str(), nullptr, 10);
  if (errno == ERANGE) return false;
  v = n;
  return true;
}

}  // namespace dembridge::math
