#include "spring_state.h"

namespace dembridge::springs {

SpringState SpringState::initial(const SpringLaw& law, bool inactive) {
  SpringState s;
  s.yield_comp = law.ylim_comp;
  s.yield_tens = law.ylim_tens;
  s.code = inactive ? kZeroForce : kRegular;
  return s;
}

}  // namespace dembridge::springs
