#include "wall_history.h"

#include <gtest/gtest.h>

using dembridge::walls::WallHistory;

TEST(WallHistory, AddFindRemoveKeepsOrder)
{
  WallHistory h;
  h.configure(3, 2);
  h.resize(2);
  EXPECT_EQ(h.count(1), 0);
  const int a = h.add(1, 10.0), b = h.add(1, 20.0), c = h.add(1, 30.0);
  EXPECT_EQ(h.add(1, 40.0), -1);  // full
  h.values(1, a)[0] = 1.5;
  h.values(1, b)[1] = 2.5;
  h.values(1, c)[0] = 3.5;
  EXPECT_EQ(h.find(1, 20.0), 1);
  h.remove(1, a);
  EXPECT_EQ(h.count(1), 2);
  EXPECT_EQ(h.key(1, 0), 20.0);
  EXPECT_EQ(h.values(1, 0)[1], 2.5);
  EXPECT_EQ(h.values(1, 1)[0], 3.5);
  EXPECT_EQ(h.find(1, 10.0), -1);
  EXPECT_EQ(h.count(0), 0);
}

TEST(WallHistory, PackUnpackAndCopy)
{
  WallHistory h;
  h.configure(4, 3);
  h.resize(3);
  h.add(0, 7.0);
  h.values(0, 0)[2] = -1.25;
  double buf[32];
  const int n = h.pack(0, buf);
  EXPECT_EQ(n, h.packed_size(0));
  EXPECT_EQ(n, 1 + 4);
  EXPECT_EQ(h.unpack(2, buf), n);
  EXPECT_EQ(h.key(2, 0), 7.0);
  EXPECT_EQ(h.values(2, 0)[2], -1.25);
  h.copy(2, 1);
  EXPECT_EQ(h.values(1, 0)[2], -1.25);
  h.clear(1);
  EXPECT_EQ(h.count(1), 0);
}
