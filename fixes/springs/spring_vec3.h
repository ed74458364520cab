// The spring kernels speak the math layer's vectors (math/vec3.h; no Eigen in the per-step path).
#pragma once

#include "math/vec3.h"

namespace dembridge::springs {
using namespace dembridge::math;
}  // namespace dembridge::springs
