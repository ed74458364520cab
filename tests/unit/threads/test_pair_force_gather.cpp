// PairForceGather against the serial scatter loop it replaces (the loop of PairGran::compute):
// the gathered forces and torques must be bit-identical, whatever the blocks and the parts the
// deferred pass is split into, with newton off (only owned atoms receive j-shares) and on.
#include "pair_force_gather.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

using dembridge::threads::PairForceGather;

namespace {

constexpr int kNeighMask = 0x1FFFFFFF;

struct HalfList {  // a random half list in LAMMPS's layout, with special bits on some entries
  std::vector<int> ilist, numneigh;
  std::vector<std::vector<int>> rows;
  std::vector<int *> firstneigh;
};

HalfList random_list(int nlocal, int nall, int inum, std::mt19937 &rng)
{
  HalfList L;
  std::vector<int> atoms(nlocal);
  for (int k = 0; k < nlocal; k++) atoms[k] = k;
  std::shuffle(atoms.begin(), atoms.end(), rng);  // list order differs from atom order
  L.ilist.assign(atoms.begin(), atoms.begin() + inum);
  L.numneigh.assign(nall, 0);
  L.rows.resize(nall);
  L.firstneigh.assign(nall, nullptr);
  std::uniform_int_distribution<int> nn(0, 12), anyatom(0, nall - 1), special(0, 3);
  for (int i : L.ilist) {
    const int n = nn(rng);
    for (int jj = 0; jj < n; jj++) {
      int j = anyatom(rng);
      if (j == i) continue;
      L.rows[i].push_back(j | (special(rng) << 30));
    }
    L.numneigh[i] = int(L.rows[i].size());
    L.firstneigh[i] = L.rows[i].data();
  }
  return L;
}

struct Contact {
  double F[3], Ti[3], Tj[3];
  bool touching;
};

}  // namespace

static void check_gather_equals_serial(bool newton)
{
  std::mt19937 rng(newton ? 7 : 3);
  const int nlocal = 300, nall = 420, inum = 280;
  HalfList L = random_list(nlocal, nall, inum, rng);
  const int nreceive = newton ? nall : nlocal;
  std::uniform_real_distribution<double> val(-1e3, 1e3);
  std::bernoulli_distribution touch(0.6);

  std::vector<double> f0(3 * nall), t0(3 * nall);
  for (auto &v : f0) v = val(rng) * 1e-7;
  for (auto &v : t0) v = val(rng) * 1e-5;
  std::vector<std::vector<Contact>> contacts(nall);
  for (int i : L.ilist)
    for (int jj = 0; jj < L.numneigh[i]; jj++) {
      Contact c{};
      for (int k = 0; k < 3; k++) c.F[k] = val(rng), c.Ti[k] = val(rng), c.Tj[k] = val(rng);
      c.touching = touch(rng);
      contacts[i].push_back(c);
    }

  // the serial loop
  std::vector<double> fs = f0, ts = t0;
  for (int i : L.ilist)
    for (int jj = 0; jj < L.numneigh[i]; jj++) {
      const Contact &c = contacts[i][jj];
      if (!c.touching) continue;
      const int j = L.firstneigh[i][jj] & kNeighMask;
      for (int k = 0; k < 3; k++) fs[3 * i + k] += c.F[k], ts[3 * i + k] += c.Ti[k];
      if (j < nreceive)
        for (int k = 0; k < 3; k++) fs[3 * j + k] -= c.F[k], ts[3 * j + k] += c.Tj[k];
    }

  PairForceGather g;
  for (int split : {1, 2, 3, 7}) {
    if (split == 3) {  // the rebuild phases as threads would run them: blocks and atom ranges in any order
      g.index(inum, L.ilist.data(), L.numneigh.data(), nreceive, split);
      for (int b = split - 1; b >= 0; b--) g.mark_block(b, L.ilist.data(), L.numneigh.data(), L.firstneigh.data(), kNeighMask);
      g.resolve(nreceive / 2, nreceive);
      g.resolve(0, nreceive / 2);
    } else {
      g.build(inum, L.ilist.data(), L.numneigh.data(), L.firstneigh.data(), kNeighMask, nreceive, split);
    }
    ASSERT_EQ(split, g.nblocks());
    std::vector<double> fg = f0, tg = t0;
    const bool keep_all = split == 3;
    // pass 1 block by block in reverse order (threads run in any order relative to each other)
    for (int b = split - 1; b >= 0; b--) {
      g.begin_block(b, keep_all);
      for (int ii = g.block_begin(b); ii < g.block_begin(b + 1); ii++) {
        const int i = L.ilist[ii];
        for (int jj = 0; jj < L.numneigh[i]; jj++) {
          const Contact &c = contacts[i][jj];
          if (!c.touching) continue;
          g.add(b, i, L.firstneigh[i][jj] & kNeighMask, c.F, c.Ti, c.Tj, fg.data(), tg.data());
          if (keep_all) g.keep(g.first_pair(ii) + jj, c.F);
        }
      }
    }
    for (int part = split - 1; part >= 0; part--) g.apply_deferred(part, split, fg.data(), tg.data());
    EXPECT_EQ(0, std::memcmp(fg.data(), fs.data(), fs.size() * sizeof(double))) << "forces, " << split << " blocks";
    EXPECT_EQ(0, std::memcmp(tg.data(), ts.data(), ts.size() * sizeof(double))) << "torques, " << split << " blocks";
    int deferred = 0;
    for (int b = 0; b < split; b++) deferred += g.ndeferred_atoms(b);
    EXPECT_EQ(0, g.ndeferred_atoms(0));
    if (split == 1) {
      EXPECT_EQ(0, deferred);
    } else {
      EXPECT_GT(deferred, 0);  // random lists: the deferred pass is exercised
    }
    if (keep_all) {  // every touching contact kept, with its force, in its slot
      for (int ii = 0; ii < inum; ii++) {
        const int i = L.ilist[ii];
        for (int jj = 0; jj < L.numneigh[i]; jj++) {
          const Contact &c = contacts[i][jj];
          ASSERT_EQ(c.touching, g.kept(g.first_pair(ii) + jj));
          if (c.touching) {
            EXPECT_EQ(0, std::memcmp(c.F, g.kept_force(g.first_pair(ii) + jj), sizeof c.F));
          }
        }
      }
    }
  }
  // the gather must actually have changed something (the test is not vacuous)
  EXPECT_NE(0, std::memcmp(fs.data(), f0.data(), fs.size() * sizeof(double)));
}

TEST(PairForceGather, BitIdenticalToSerialLoopNewtonOff) { check_gather_equals_serial(false); }
TEST(PairForceGather, BitIdenticalToSerialLoopNewtonOn) { check_gather_equals_serial(true); }

TEST(PairForceGather, SeparatedDeferredPairContributesNothing)
{
  // atoms 0 and 1, each with a row, rows in two blocks: block 0 names both, so block 1 defers both
  int ilist[2] = {0, 1}, numneigh[2] = {1, 1}, row0[1] = {1}, row1[1] = {0};
  int *firstneigh[2] = {row0, row1};
  PairForceGather g;
  g.build(2, ilist, numneigh, firstneigh, kNeighMask, 2, 2);
  ASSERT_EQ(2, g.ndeferred_atoms(1));
  const double F[3] = {1, 2, 3}, T[3] = {4, 5, 6};
  double f[6] = {0, 0, 0, 0, 0, 0}, t[6] = {0, 0, 0, 0, 0, 0};
  g.begin_block(1, false);
  g.add(1, 1, 0, F, T, T, f, t);  // deferred: nothing written yet
  for (int k = 0; k < 6; k++) EXPECT_EQ(0.0, f[k] + t[k]);
  g.begin_block(1, false);  // next step: the pair separated
  g.apply_deferred(0, 1, f, t);
  for (int k = 0; k < 6; k++) EXPECT_EQ(0.0, f[k] + t[k]);
}

TEST(PairForceGather, SpatiallySortedListHasThinBoundary)
{
  // a 1-d chain sorted in space (neighbours within 3 places): two blocks meet in a few atoms
  const int n = 1000;
  std::vector<int> ilist(n), numneigh(n);
  std::vector<std::vector<int>> rows(n);
  std::vector<int *> firstneigh(n);
  for (int i = 0; i < n; i++) {
    ilist[i] = i;
    for (int d = 1; d <= 3 && i + d < n; d++) rows[i].push_back(i + d);
    numneigh[i] = int(rows[i].size());
    firstneigh[i] = rows[i].data();
  }
  PairForceGather g;
  g.build(n, ilist.data(), numneigh.data(), firstneigh.data(), kNeighMask, n, 2);
  EXPECT_LE(g.ndeferred_atoms(1), 3);
  EXPECT_GT(g.ndeferred_atoms(1), 0);
}
