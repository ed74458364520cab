// Pins the operation order of Parmec's ISPC build that rotation_step(float_taylor) reproduces (Q27): the
// product J⁻¹ B is summed with the MIDDLE product fused first, fma(a2, b2, fma(a1, b1, a0 b0)), unlike the
// other product sums (first product fused first). The expected bits come from fused_order_reference.py
// (exact rational fma, independent of fixes/rigid); the case is one where the two orders differ in the last
// bit of Ω'x, so the test fails if the order of that helper changes.
#include <gtest/gtest.h>

#include "body_rotation.h"

using dembridge::rigid::Mat3;
using dembridge::rigid::Vec3;

TEST(FusedOrder, InverseInertiaTimesBSumsTheMiddleProductFirst)
{
  Mat3 J;
  J << 2.0, 0.3, 0.1, 0.3, 3.0, 0.2, 0.1, 0.2, 4.0;
  Mat3 Jinv;  // J's exact inverse, rounded (fused_order_reference.py)
  Jinv << 0x1.041c45db123f3p-1, -0x1.9a9bef8ee893bp-5, -0x1.4e0e0ca855146p-7,  //
      -0x1.9a9bef8ee893bp-5, 0x1.5b89f32b20839p-2, -0x1.018029c1c1951p-6,      //
      -0x1.4e0e0ca855146p-7, -0x1.018029c1c1951p-6, 0x1.0110cfbd8978bp-2;
  // Λ = I and Ω = 0: exp(−h/2 Ω) = I and B = h/2 T exactly, so A = J⁻¹ B is the only order-sensitive input
  const auto step = dembridge::rigid::rotation_step(J, Jinv, Mat3::Identity(), Vec3::Zero(), Vec3(1.0, 3.0, 2.0),
                                                    1.0, false, true);
  const Vec3 middle_first(0x1.1081cb5351678p-2, 0x1.ed24e82f7f990p-1, 0x1.c30fa3174ae13p-2);
  const double first_first_x = 0x1.1081cb5351677p-2;  // Ω'x with A summed first product first
  EXPECT_EQ(step.W[0], middle_first[0]);
  EXPECT_EQ(step.W[1], middle_first[1]);
  EXPECT_EQ(step.W[2], middle_first[2]);
  EXPECT_NE(step.W[0], first_first_x);  // the case tells the two orders apart
}
