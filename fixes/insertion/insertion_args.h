// Strict readers for the arguments of the insertion fixes: each throws std::invalid_argument with
// the keyword and what was expected (LIGGGHTS reads them with atof/atoi and takes garbage as 0).
#pragma once

#include <string>

namespace dembridge::insertion {

double number_arg(const std::string &text, const std::string &keyword);
int integer_arg(const std::string &text, const std::string &keyword);
bool yes_no_arg(const std::string &text, const std::string &keyword);

}  // namespace dembridge::insertion
