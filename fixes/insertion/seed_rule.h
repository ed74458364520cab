// LIGGGHTS 3.8's rule for the seeds of the insertion fixes: an integer, a prime > 10000, <= INT_MAX.
#pragma once

#include <string>

namespace dembridge::insertion {

// The seed written in the deck, or throws std::invalid_argument with what was wrong.
int parse_seed(const std::string &text);
bool is_prime(long n);

}  // namespace dembridge::insertion
