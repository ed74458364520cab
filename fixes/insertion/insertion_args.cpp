#include "insertion_args.h"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace dembridge::insertion {

double number_arg(const std::string &text, const std::string &keyword)
{
  char *end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw std::invalid_argument("'" + keyword + "' expects a number, got '" + text + "'");
  return v;
}

int integer_arg(const std::string &text, const std::string &keyword)
{
  char *end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v > INT_MAX || v < INT_MIN)
    throw std::invalid_argument("'" + keyword + "' expects an integer, got '" + text + "'");
  return static_cast<int>(v);
}

bool yes_no_arg(const std::string &text, const std::string &keyword)
{
  if (text == "yes") return true;
  if (text == "no") return false;
  throw std::invalid_argument("'" + keyword + "' expects 'yes' or 'no', got '" + text + "'");
}

}  // namespace dembridge::insertion
