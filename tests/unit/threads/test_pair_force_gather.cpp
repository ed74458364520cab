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
  g.build(inum, L.ilist.data(), L.numneigh.data(), L.firstneigh.data(), kNeighMask, nall, nreceive);
  for (int split : {1, 2, 3, 7}) {
    // pass 1 in 'split' ii ranges, stored in reverse range order (threads finish in any order)
    for (int part = split - 1; part >= 0; part--) {
      const int lo = inum * part / split, hi = inum * (part + 1) / split;
      g.clear_contacts(lo, hi);
      for (int ii = lo; ii < hi; ii++) {
        const int i = L.ilist[ii];
        for (int jj = 0; jj < L.numneigh[i]; jj++)
          if (contacts[i][jj].touching) g.store(g.first_pair(ii) + jj, contacts[i][jj].F, contacts[i][jj].Ti, contacts[i][jj].Tj);
      }
    }
    std::vector<double> fg = f0, tg = t0;
    std::vector<double *> fp(nall), tp(nall);
    for (int k = 0; k < nall; k++) fp[k] = &fg[3 * k], tp[k] = &tg[3 * k];
    for (int part = 0; part < split; part++) g.gather(nreceive * part / split, nreceive * (part + 1) / split, fp.data(), tp.data());
    EXPECT_EQ(0, std::memcmp(fg.data(), fs.data(), fs.size() * sizeof(double))) << "forces, " << split << " ranges";
    EXPECT_EQ(0, std::memcmp(tg.data(), ts.data(), ts.size() * sizeof(double))) << "torques, " << split << " ranges";
  }
  // the gather must actually have changed something (the test is not vacuous)
  EXPECT_NE(0, std::memcmp(fs.data(), f0.data(), fs.size() * sizeof(double)));
}

TEST(PairForceGather, BitIdenticalToSerialLoopNewtonOff) { check_gather_equals_serial(false); }
TEST(PairForceGather, BitIdenticalToSerialLoopNewtonOn) { check_gather_equals_serial(true); }

TEST(PairForceGather, ClearedContactsContributeNothing)
{
  int ilist[1] = {0}, numneigh[2] = {1, 0}, row0[1] = {1};
  int *firstneigh[2] = {row0, nullptr};
  PairForceGather g;
  g.build(1, ilist, numneigh, firstneigh, kNeighMask, 2, 2);
  const double F[3] = {1, 2, 3}, T[3] = {4, 5, 6};
  g.clear_contacts(0, 1);
  g.store(g.first_pair(0), F, T, T);
  g.clear_contacts(0, 1);  // next step: the pair separated
  double f[2][3] = {{0, 0, 0}, {0, 0, 0}}, t[2][3] = {{0, 0, 0}, {0, 0, 0}};
  double *fp[2] = {f[0], f[1]}, *tp[2] = {t[0], t[1]};
  g.gather(0, 2, fp, tp);
  for (int k = 0; k < 3; k++) EXPECT_EQ(0.0, f[0][k] + f[1][k] + t[0][k] + t[1][k]);
}
