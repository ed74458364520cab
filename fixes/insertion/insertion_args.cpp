#include "insertion_args.h"
#include "math/number_word.h"

#include <climits>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace dembridge::insertion {

double number_arg(const std::string &text, const std::string &keyword)
{
  double v;
  if (!math::read_number(text, v))
    throw std::invalid_argument("'" + keyword + "' expects a number, got '" + text + "'");
  return v;
}

int integer_arg(const std::string &text, const std::string &keyword)
{
  long long v;
  if (!math::read_integer(text, v) || v > INT_MAX || v < INT_MIN)
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
