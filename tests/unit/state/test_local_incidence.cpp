// LocalIncidence + OrderedSums::sum_with: a local atom's contributions summed straight from per-evaluation
// results in key order, merged with entries received from another "rank", equal bit for bit to the sum
// the test forms itself in key order (the same as add()ing every contribution, then sum()); the lists are
// rebuilt only when the (key, atom, atom) triples change.
#include "local_incidence.h"
#include "ordered_sums.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using dembridge::state::LocalIncidence;
using dembridge::state::OrderedSums;

TEST(LocalIncidence, TermsOfEachAtomInKeyOrderRebuiltOnlyOnChange)
{
  // evaluations r: keys 5, 2, 9, 0 between local atoms (0,1), (1,-1), (2,0), (1,2)
  const int keys[4] = {5, 2, 9, 0}, a1[4] = {0, 1, 2, 1}, a2[4] = {1, -1, 0, 2};
  LocalIncidence inc;
  EXPECT_TRUE(inc.update(3, 4, keys, a1, a2));
  EXPECT_FALSE(inc.update(3, 4, keys, a1, a2));
  auto list = [&](int i) {
    std::vector<std::vector<int>> out;
    for (auto *t = inc.begin(i); t != inc.end(i); ++t) out.push_back({t->key, t->r, t->side});
    return out;
  };
  EXPECT_EQ(list(0), (std::vector<std::vector<int>>{{5, 0, 0}, {9, 2, 1}}));
  EXPECT_EQ(list(1), (std::vector<std::vector<int>>{{0, 3, 0}, {2, 1, 0}, {5, 0, 1}}));
  EXPECT_EQ(list(2), (std::vector<std::vector<int>>{{0, 3, 1}, {9, 2, 0}}));
  const int moved[4] = {0, 1, 2, 0};  // evaluation 3 now on atom 0
  EXPECT_TRUE(inc.update(3, 4, keys, moved, a2));
  EXPECT_EQ(list(0), (std::vector<std::vector<int>>{{0, 3, 0}, {5, 0, 0}, {9, 2, 1}}));
}

TEST(OrderedSums, SumWithLocalTermsEqualsAddingThemThenSum)
{
  const int n = 16;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::vector<double>> v(n);
  for (int k = 0; k < n; k++) v[k] = {u(rng) * std::pow(10.0, k % 7), u(rng) * 1e-3};
  std::vector<std::pair<long, long>> pairs;
  for (int k = 0; k < n; k++) pairs.emplace_back(100 + k, 1);  // every entity touches atom tag 1
  for (unsigned shuffle = 0; shuffle < 20; shuffle++) {
    std::vector<int> order(n);
    for (int k = 0; k < n; k++) order[k] = k;
    std::shuffle(order.begin(), order.end(), std::mt19937(shuffle));
    OrderedSums all, split;
    all.configure(2, pairs);
    split.configure(2, pairs);
    all.reset(1);
    split.reset(1);
    std::vector<OrderedSums::Term> local;
    for (int c = 0; c < n; c++) {
      const int k = order[c];
      const double sign = k % 3 ? 1.0 : -1.0;
      ASSERT_TRUE(all.add(0, k, v[k].data(), sign));
      if (c < n / 3)
        ASSERT_TRUE(split.add(0, k, v[k].data(), sign));  // "received" entries
      else
        local.push_back({k, v[k].data(), sign});
    }
    std::sort(local.begin(), local.end(), [](const auto &a, const auto &b) { return a.key < b.key; });
    double expect[2], got[2], none[2];
    all.sum(0, expect);
    split.sum_with(0, local.data(), static_cast<int>(local.size()), got);
    EXPECT_EQ(got[0], expect[0]);
    EXPECT_EQ(got[1], expect[1]);
    OrderedSums empty;
    empty.configure(2, pairs);
    empty.reset(1);
    std::vector<OrderedSums::Term> every;
    for (int k = 0; k < n; k++) every.push_back({k, v[k].data(), k % 3 ? 1.0 : -1.0});
    empty.sum_with(0, every.data(), n, none);
    EXPECT_EQ(none[0], expect[0]);
    EXPECT_EQ(none[1], expect[1]);
  }
}
