// Pins the order of the C++ products of Parmec's joints.cpp (macros.h NNMUL/NTMUL/NVMUL/TVMUL: k = 0, 1, 2 from
// the left, unfused) that macro_mul/macro_mv reproduce. With a row (1, 1, 1) and b = (1, 2^-53, 2^-53) the left
// sum is (1 + 2^-53) + 2^-53 = 1 (each addition ties to even), while a0 b0 + (a1 b1 + a2 b2), the order of
// Eigen's fixed-size products in their third row, is 1 + 2^-52: every row must give exactly 1.
#include <gtest/gtest.h>

#include <cmath>

#include "body_rotation.h"

using dembridge::rigid::Mat3;
using dembridge::rigid::Vec3;
namespace rg = dembridge::rigid;

TEST(MacroOrder, ProductsSumFromTheLeft)
{
  const double e = std::ldexp(1.0, -53);
  const Mat3 ones = Mat3::Constant(1.0);
  const Vec3 b(1.0, e, e);
  Mat3 B;  // every column b
  B << 1.0, 1.0, 1.0, e, e, e, e, e, e;
  const Vec3 mv = rg::macro_mv(ones, b), tmv = rg::macro_tmv(ones, b);
  const Mat3 mm = rg::macro_mul(ones, B), mt = rg::macro_mul_t(ones, Mat3(B.transpose()));
  for (int i = 0; i < 3; i++) {
    EXPECT_EQ(mv[i], 1.0) << i;
    EXPECT_EQ(tmv[i], 1.0) << i;
    for (int j = 0; j < 3; j++) {
      EXPECT_EQ(mm(i, j), 1.0) << i << j;
      EXPECT_EQ(mt(i, j), 1.0) << i << j;
    }
  }
  EXPECT_EQ(1.0 + (e + e), 1.0 + 2.0 * e);  // the other order differs: the case tells them apart
  EXPECT_NE(1.0 + 2.0 * e, 1.0);
}
