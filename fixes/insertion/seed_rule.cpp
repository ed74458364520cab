#include "seed_rule.h"
#include "math/number_word.h"

#include <climits>
#include <cstdlib>
#include <stdexcept>

namespace dembridge::insertion {

bool is_prime(long n)
{
  if (n < 2) return false;
  if (n % 2 == 0) return n == 2;
  for (long d = 3; d * d <= n; d += 2)
    if (n % d == 0) return false;
  return true;
}

int parse_seed(const std::string &text)
{
  if (!math::is_integer_word(text)) throw std::invalid_argument("seed '" + text + "' is not an integer");
  long long v = 0;
  if (!math::read_integer(text, v) || v > INT_MAX)
    throw std::invalid_argument("seed " + text + " is larger than INT_MAX (" + std::to_string(INT_MAX) + ")");
  // LIGGGHTS's message: "It is required that the random seed value is > 10000 and a prime number"
  if (v < 10000 || !is_prime(static_cast<long>(v)))
    throw std::invalid_argument("seed " + text + ": it is required that the random seed value is > 10000 and a prime number"
                                " (e.g. 15485863, 15485867, 32452843, 32452867, 49979687)");
  return static_cast<int>(v);
}

}  // namespace dembridge::insertion
