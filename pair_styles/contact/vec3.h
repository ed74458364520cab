// The contact laws' 3-vector products on plain double[3] and Lanes4 (math/vec3.h), and the length.
#pragma once

#include "lane_math.h"
#include "math/vec3.h"

namespace dembridge::gran {

using math::cross3;
using math::dot3;
using math::kPi;
// R: double, or Lanes4 (lane_math.h)
template <class R> [[gnu::always_inline]] inline R len3(const R *a) { return lane_sqrt(dot3(a, a)); }

}  // namespace dembridge::gran
