// PairForceGather against the serial scatter loop it replaces (the loop of PairGran::compute):
// the gathered forces and torques must be bit-identical, whatever the atom ranges the passes are
// split into, with newton off (only owned atoms receive j-shares) and on.
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
    g.build(inum, L.ilist.data(), L.numneigh.data(), L.firstneigh.data(), kNeighMask, nall, nreceive, split);
    ASSERT_EQ(split, g.nblocks());
    std::vector<double> fg = f0, tg = t0;
    std::vector<double *> fp(nall), tp(nall);
    for (int k = 0; k < nall; k++) fp[k] = &fg[3 * k], tp[k] = &tg[3 * k];
    // pass 1 block by block in reverse order (threads run in any order relative to each other)
    for (int b = split - 1; b >= 0; b--) {
      g.clear_contacts(g.block_begin(b), g.block_begin(b + 1));
      for (int ii = g.block_begin(b); ii < g.block_begin(b + 1); ii++) {
        const int i = L.ilist[ii];
        for (int jj = 0; jj < L.numneigh[i]; jj++) {
          const Contact &c = contacts[i][jj];
          if (c.touching)
            g.add(g.first_pair(ii) + jj, i, L.firstneigh[i][jj] & kNeighMask, c.F, c.Ti, c.Tj, fp.data(), tp.data(), split == 3);
        }
      }
    }
    for (int part = 0; part < split; part++)
      g.gather_boundary(g.nboundary() * part / split, g.nboundary() * (part + 1) / split, fp.data(), tp.data());
    EXPECT_EQ(0, std::memcmp(fg.data(), fs.data(), fs.size() * sizeof(double))) << "forces, " << split << " blocks";
    EXPECT_EQ(0, std::memcmp(tg.data(), ts.data(), ts.size() * sizeof(double))) << "torques, " << split << " blocks";
    if (split == 1) {
      EXPECT_EQ(0, g.nboundary());
    } else {
      EXPECT_GT(g.nboundary(), 0);  // random lists: the gather pass is exercised
    }
  }
  // the gather must actually have changed something (the test is not vacuous)
  EXPECT_NE(0, std::memcmp(fs.data(), f0.data(), fs.size() * sizeof(double)));
}

TEST(PairForceGather, BitIdenticalToSerialLoopNewtonOff) { check_gather_equals_serial(false); }
TEST(PairForceGather, BitIdenticalToSerialLoopNewtonOn) { check_gather_equals_serial(true); }

TEST(PairForceGather, SeparatedBoundaryPairContributesNothing)
{
  // atoms 0 and 1, each with a row, rows in two blocks: atom 1 is named by block 0, so on the boundary
  int ilist[2] = {0, 1}, numneigh[2] = {1, 1}, row0[1] = {1}, row1[1] = {0};
  int *firstneigh[2] = {row0, row1};
  PairForceGather g;
  g.build(2, ilist, numneigh, firstneigh, kNeighMask, 2, 2, 2);
  ASSERT_EQ(2, g.nboundary());
  const double F[3] = {1, 2, 3}, T[3] = {4, 5, 6};
  double f[2][3] = {{0, 0, 0}, {0, 0, 0}}, t[2][3] = {{0, 0, 0}, {0, 0, 0}};
  double *fp[2] = {f[0], f[1]}, *tp[2] = {t[0], t[1]};
  g.clear_contacts(0, 2);
  g.add(g.first_pair(0), 0, 1, F, T, T, fp, tp, false);
  g.clear_contacts(0, 2);  // next step: the pair separated
  g.gather_boundary(0, g.nboundary(), fp, tp);
  for (int k = 0; k < 3; k++) EXPECT_EQ(0.0, f[0][k] + f[1][k] + t[0][k] + t[1][k]);
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
  g.build(n, ilist.data(), numneigh.data(), firstneigh.data(), kNeighMask, n, n, 2);
  EXPECT_LE(g.nboundary(), 3);
  EXPECT_GT(g.nboundary(), 0);
}
