#include "spring_law.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dembridge::springs {

void SpringLaw::validate() const {
  if (!spring) throw std::invalid_argument("spring: a spring table is required");
  if (dashpot && ratio_dashpot())
    throw std::invalid_argument("spring: give the dashpot either as a table or as a critical damping ratio, not both");
  if (!(std::isfinite(damping_ratio)))
    throw std::invalid_argument("spring: damping ratio must be finite");
  if (unload && !unload->strictly_increasing_values())
    throw std::invalid_argument("spring: unload curve must have strictly positive slopes everywhere");
  if (!(ylim_comp <= 0.0) || !(ylim_tens >= 0.0))
    throw std::invalid_argument("spring: ylim must satisfy ylim_compression <= 0 <= ylim_tension, got (" +
                                std::to_string(ylim_comp) + ", " + std::to_string(ylim_tens) + ")");
  if (!(friction >= 0.0)) throw std::invalid_argument("spring: friction must be >= 0");
  if (!(kskn >= 0.0)) throw std::invalid_argument("spring: kskn must be >= 0");
}

}  // namespace dembridge::springs
