// The joint systems' profile LU (fixes/rigid/SkylineLU) against Eigen's dense LU, its envelope skipping
// (a block-tridiagonal chain stays banded), and a zero pivot reported instead of dividing by zero.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "skyline_lu.h"

using dembridge::rigid::SkylineLU;

TEST(SkylineLU, SolvesABandedChainLikeDenseLU)
{
  const int n = 30;
  std::mt19937 g(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  SkylineLU lu(n);
  for (int r = 0; r < n; r++)
    for (int c = std::max(0, r - 4); c < std::min(n, r + 5); c++) {
      const double v = (r == c ? 10.0 : 0.0) + u(g);
      A(r, c) = v;
      lu.add(r, c, v);
    }
  Eigen::VectorXd b(n);
  for (int r = 0; r < n; r++) b[r] = u(g);
  std::vector<double> x(b.data(), b.data() + n);
  ASSERT_TRUE(lu.factorize());
  ASSERT_TRUE(lu.solve(x));
  const Eigen::VectorXd ref = A.partialPivLu().solve(b);
  for (int r = 0; r < n; r++) EXPECT_NEAR(x[r], ref[r], 1e-14) << r;
}

TEST(SkylineLU, ZeroPivotIsReported)
{
  SkylineLU lu(2);
  lu.add(0, 0, 1.0);
  lu.add(0, 1, 2.0);
  lu.add(1, 0, 1.0);
  lu.add(1, 1, 2.0);  // singular: row 2 = row 1
  EXPECT_FALSE(lu.factorize());
  std::vector<double> x{1.0, 1.0};
  EXPECT_FALSE(lu.solve(x));
}
