// RecordLists / RecordIndex: records follow their atom through copy (sort, deletion), pack/unpack
// (exchange, restart) and erase, byte for byte; the key index finds every record after each move.
#include "record_lists.h"

#include <gtest/gtest.h>

#include <vector>

using dembridge::state::RecordIndex;
using dembridge::state::RecordLists;

namespace {

// Atom a holds keys a, a + 10, ... (count a % 3); record values encode (key, position).
RecordLists filled(int natoms, int rs)
{
  RecordLists l(rs);
  l.resize(natoms);
  for (int a = 0; a < natoms; a++)
    for (int r = 0; r < a % 3; r++) {
      double *rec = l.append(a, a + 10 * r);
      for (int c = 1; c < rs; c++) rec[c] = 1000.0 * (a + 10 * r) + c + 0.125;
    }
  return l;
}

std::vector<double> contents(const RecordLists &l, int i)
{
  std::vector<double> out;
  for (int r = 0; r < l.count(i); r++) out.insert(out.end(), l.record(i, r), l.record(i, r) + l.record_size());
  return out;
}

}  // namespace

TEST(RecordLists, PackUnpackMovesAnAtomsRecordsExactly)
{
  RecordLists from = filled(8, 5), to(5);
  to.resize(8);
  std::vector<double> buf(64);
  for (int a = 0; a < 8; a++) {
    const int n = from.pack(a, buf.data());
    EXPECT_EQ(n, 1 + 5 * (a % 3));
    EXPECT_EQ(n, from.packed_size(a));
    EXPECT_EQ(to.unpack(7 - a, buf.data()), n);  // lands in another slot, as exchange does
    EXPECT_EQ(contents(to, 7 - a), contents(from, a));
  }
  EXPECT_EQ(to.total(8), from.total(8));
}

TEST(RecordLists, CopyClearAndEraseKeepTheOtherRecords)
{
  RecordLists l = filled(6, 4);
  const std::vector<double> five = contents(l, 5);
  l.copy(5, 0);  // atom 0 replaced by atom 5 (deletion / sort)
  EXPECT_EQ(contents(l, 0), five);
  l.clear(5);
  EXPECT_EQ(l.count(5), 0);
  EXPECT_EQ(contents(l, 0), five);  // the copy is independent
  // erase the first record of atom 2 (keys 2, 12): key 12 remains, intact
  const std::vector<double> two = contents(l, 2);
  l.erase(2, 0);
  ASSERT_EQ(l.count(2), 1);
  EXPECT_EQ(contents(l, 2), std::vector<double>(two.begin() + 4, two.end()));
  l.erase(2, 0);
  EXPECT_EQ(l.count(2), 0);
}

// Wall contacts: keys beyond int (mesh * 2^32 + triangle), found exactly; remove keeps the order the
// contacts began in (the mesh pass's slots and its "last flat neighbour wins" depend on it).
TEST(RecordLists, FindAndRemoveKeepTheOrderWithKeysBeyondInt)
{
  RecordLists l(3);
  l.resize(2);
  const double big = 3 * 4294967296.0 + 17;
  const double keys[4] = {5.0, big, big + 1, 0.0};
  for (int r = 0; r < 4; r++) {
    double *rec = l.append(1, keys[r]);
    EXPECT_EQ(rec[0], keys[r]);
    EXPECT_EQ(rec[1], 0.0);
    EXPECT_EQ(rec[2], 0.0);
    rec[1] = r + 0.5;
    rec[2] = -r - 0.25;
  }
  EXPECT_EQ(l.find(1, big), 1);
  EXPECT_EQ(l.find(1, big + 1), 2);
  EXPECT_EQ(l.find(1, 0.0), 3);
  EXPECT_EQ(l.find(1, 7.0), -1);
  EXPECT_EQ(l.find(0, 5.0), -1);
  l.remove(1, 1);  // big goes; 5, big + 1, 0 stay in that order with their values
  ASSERT_EQ(l.count(1), 3);
  const double kept[3] = {5.0, big + 1, 0.0}, first[3] = {0.5, 2.5, 3.5};
  for (int r = 0; r < 3; r++) {
    EXPECT_EQ(l.record(1, r)[0], kept[r]);
    EXPECT_EQ(l.record(1, r)[1], first[r]);
  }
  EXPECT_EQ(l.find(1, big), -1);
  l.remove(1, 2);
  l.remove(1, 0);
  ASSERT_EQ(l.count(1), 1);
  EXPECT_EQ(l.record(1, 0)[0], big + 1);
  EXPECT_EQ(l.record(1, 0)[2], -2.25);
  EXPECT_EQ(l.count(0), 0);
}

TEST(RecordIndex, FindsEachKeyAfterEveryMove)
{
  RecordLists l = filled(9, 3);
  RecordIndex index;
  const int nkeys = 30;
  auto check = [&](int n) {
    std::vector<int> seen(nkeys, 0);
    for (int a = 0; a < n; a++)
      for (int r = 0; r < l.count(a); r++) {
        const int key = l.key(a, r);
        seen[key] = 1;
        EXPECT_EQ(index.find(l, n, nkeys, key), std::make_pair(a, r));
      }
    for (int key = 0; key < nkeys; key++) {
      if (!seen[key]) {
        EXPECT_EQ(index.find(l, n, nkeys, key), std::make_pair(-1, -1)) << key;
      }
    }
  };
  check(9);
  l.copy(8, 1);  // atom 1's records gone, atom 8's now also at 1: with 8 local atoms only slot 1 holds them
  check(8);
  std::vector<double> buf(16);
  l.pack(4, buf.data());
  l.unpack(0, buf.data());
  l.clear(4);
  check(8);
  EXPECT_EQ(index.find(l, 8, nkeys, -1), std::make_pair(-1, -1));
  EXPECT_EQ(index.find(l, 8, nkeys, nkeys), std::make_pair(-1, -1));
}

TEST(RecordLists, ClearReleasesMemory)
{
  RecordLists l = filled(3, 50);
  // atom 1: one record of 50 doubles, atom 2: two (the second append doubles the capacity to 100), each
  // block with malloc's header; and the three atoms' list objects
  const double lists = 3 * sizeof(std::vector<double>);
  EXPECT_EQ(l.bytes(3), lists + (50 * 8 + RecordLists::kChunkHeader) + (100 * 8 + RecordLists::kChunkHeader));
  for (int a = 0; a < 3; a++) l.clear(a);
  EXPECT_EQ(l.bytes(3), lists);  // the records are released; the list objects stay with the atom slots
}
