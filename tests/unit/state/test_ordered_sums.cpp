// OrderedSums: an atom's contributions summed in key order whatever the order they arrived in and
// whichever "rank" evaluated them (a ghost's entries packed on one side and unpacked on the other), bit
// for bit equal to the sum the test forms itself in key order; hubs beyond kMaxOrdered fall back to a
// running sum (equal within round-off).
#include "ordered_sums.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using dembridge::state::OrderedSums;

namespace {

struct Entry {
  int key;
  double v[2];
};

// Values of very different magnitude, so that the summation order shows in the last bits.
std::vector<Entry> entries(int n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Entry> e;
  for (int k = 0; k < n; k++) e.push_back({k, {u(rng) * std::pow(10.0, k % 7), u(rng) * 1e-3}});
  return e;
}

void reference_sum(std::vector<Entry> e, double *out)
{
  std::sort(e.begin(), e.end(), [](const Entry &a, const Entry &b) { return a.key < b.key; });
  out[0] = out[1] = 0.0;
  for (const Entry &x : e)
    for (int c = 0; c < 2; c++) out[c] += x.v[c];
}

}  // namespace

TEST(OrderedSums, SumIsInKeyOrderWhateverTheArrivalAndTheRank)
{
  const int n = 12;
  std::vector<std::pair<long, long>> pairs;
  for (int k = 0; k < n; k++) pairs.emplace_back(100 + k, 1);  // every entity touches atom tag 1
  std::vector<Entry> all = entries(n, 7);
  double expect[2];
  reference_sum(all, expect);

  for (unsigned shuffle = 0; shuffle < 20; shuffle++) {
    std::vector<Entry> order = all;
    std::shuffle(order.begin(), order.end(), std::mt19937(shuffle));
    // "rank A" owns atom 0 (tag 1) and evaluates the first half; "rank B" has atom 1 as a ghost of it.
    OrderedSums a, b;
    const int comm = a.configure(2, pairs);
    b.configure(2, pairs);
    EXPECT_EQ(comm, 1 + 3 * n);
    a.reset(1);
    b.reset(2);
    for (int k = 0; k < n; k++) {
      const Entry &x = order[k];
      if (k < n / 2)
        ASSERT_TRUE(a.add(0, x.key, x.v, 1.0));
      else
        ASSERT_TRUE(b.add(1, x.key, x.v, 1.0));
    }
    std::vector<double> buf(comm);
    EXPECT_LE(b.pack(1, 1, buf.data()), comm);
    const int list[1] = {0};
    ASSERT_TRUE(a.unpack(1, list, buf.data()));
    double got[2];
    a.sum(0, got);
    EXPECT_EQ(got[0], expect[0]);
    EXPECT_EQ(got[1], expect[1]);
  }
}

TEST(OrderedSums, SignAndOverflow)
{
  OrderedSums s;
  s.configure(2, {{1, 2}});  // one entity on atoms 1 and 2: one entry per atom
  s.reset(2);
  const double v[2] = {1.5, -2.0};
  EXPECT_TRUE(s.add(0, 0, v, 1.0));
  EXPECT_TRUE(s.add(1, 0, v, -1.0));
  EXPECT_FALSE(s.add(1, 0, v, -1.0));  // more entries than configured: the caller's internal error
  double out[2];
  s.sum(1, out);
  EXPECT_EQ(out[0], -1.5);
  EXPECT_EQ(out[1], 2.0);
  EXPECT_TRUE(s.empty(1) == false);
  s.reset(2);
  EXPECT_TRUE(s.empty(0) && s.empty(1));
}

TEST(OrderedSums, HubsBeyondTheLimitUseARunningSum)
{
  const int n = OrderedSums::kMaxOrdered + 1;
  std::vector<std::pair<long, long>> pairs;
  for (int k = 0; k < n; k++) pairs.emplace_back(1, 1000 + k);  // a hub: atom tag 1 in every entity
  OrderedSums s;
  s.configure(2, pairs);
  EXPECT_FALSE(s.ordered());
  s.reset(1);
  std::vector<Entry> all = entries(n, 3);
  for (const Entry &x : all) ASSERT_TRUE(s.add(0, x.key, x.v, 1.0));
  double expect[2], got[2];
  reference_sum(all, expect);
  s.sum(0, got);
  EXPECT_NEAR(got[0], expect[0], 1e-9 * std::fabs(expect[0]) + 1e-12);
  EXPECT_NEAR(got[1], expect[1], 1e-12);
}
