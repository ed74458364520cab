// The mesh geometry speaks the math layer's vectors and quaternions (math/vec3.h, math/quaternion.h).
#pragma once

#include "math/quaternion.h"
#include "math/vec3.h"

namespace dembridge::mesh {
using namespace dembridge::math;
}  // namespace dembridge::mesh
