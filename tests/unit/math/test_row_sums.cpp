// math::add_into / subtract_from (math/vec3.h): the pair sinks' row updates must round every element
// exactly as row[k] += v[k] does, at any alignment of the row (LAMMPS's rows are 24 bytes apart).
#include "math/vec3.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace {

using dembridge::math::add_into;
using dembridge::math::subtract_from;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(RowSums, EveryElementRoundsAsTheScalarSum)
{
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-60, 60);
  const int rows = 1000;
  std::vector<double> a(3 * rows + 1), v(3 * rows + 1);
  for (std::size_t k = 0; k < a.size(); k++) {
    a[k] = std::ldexp(mant(rng), expo(rng));
    v[k] = std::ldexp(mant(rng), expo(rng));
  }
  for (int shift = 0; shift < 2; shift++) {  // rows at 8-byte and 16-byte alignment
    std::vector<double> sum = a, diff = a;
    for (int r = 0; r < rows; r++) {
      double *s = sum.data() + shift + 3 * r, *d = diff.data() + shift + 3 * r;
      const double *w = v.data() + 3 * r;
      add_into(s, w);
      subtract_from(d, w);
      for (int k = 0; k < 3; k++) {
        const double x = a[shift + 3 * r + k];
        ASSERT_TRUE(same_bits(s[k], x + w[k])) << r << " " << k;
        ASSERT_TRUE(same_bits(d[k], x - w[k])) << r << " " << k;
      }
    }
    if (shift == 0) {
      EXPECT_TRUE(same_bits(sum.back(), a.back()));  // never past the last row
    }
  }
}

TEST(RowSums, SpecialValues)
{
  double row[3] = {1.0, -0.0, INFINITY};
  const double v[3] = {0x1p-53, 0.0, -INFINITY};
  add_into(row, v);
  EXPECT_EQ(row[0], 1.0);  // ties to even
  EXPECT_FALSE(std::signbit(row[1]));  // -0 + +0 = +0
  EXPECT_TRUE(std::isnan(row[2]));
  double r2[3] = {0.0, 1.0, 2.0};
  subtract_from(r2, r2);  // the row itself as the operand
  EXPECT_EQ(r2[0], 0.0);
  EXPECT_EQ(r2[1], 0.0);
  EXPECT_EQ(r2[2], 0.0);
}

}  // namespace
