// fix parmec/spring 'order parmec': Parmec's per-body running sums of the spring forces (forces.ispc's order).
#include "fix_parmec_spring.h"

#include <algorithm>
#include <numeric>

using namespace LAMMPS_NS;

namespace dembridge {

// Parmec's spring loop (forces.ispc, one task) walks the springs sorted by (part1, part2) and keeps one
// running sum per body side: the forces of consecutive springs with the same part1 (a "run") are summed,
// then added to part1's force when part1 changes; likewise for part2 among the springs with a part2 (a
// spring to space does not end a part2 run), subtracted when part2 changes; at the end the part1 sum, then
// the part2 sum. rank = (the moment its run is added) * n + (position in the sorted order), so an atom's
// contributions sorted by rank are its runs in Parmec's order, each in spring order.
void FixParmecSpring::parmec_schedule()
{
  const int n = static_cast<int>(defs_.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [this](int a, int b) {
    return defs_[a].tag1 != defs_[b].tag1 ? defs_[a].tag1 < defs_[b].tag1 : defs_[a].tag2 < defs_[b].tag2;
  });
  std::vector<int> run_of(2 * std::size_t(n), -1), added;  // run of each (spring, side); when a run is added
  int jrun = -1, krun = -1, moment = 0;
  tagint j0 = 0, k0 = 0;
  for (int p = 0; p < n; p++) {
    const SpringDef &d = defs_[order[p]];
    if (jrun < 0 || d.tag1 != j0) {
      if (jrun >= 0) added[jrun] = moment++;
      jrun = static_cast<int>(added.size());
      added.push_back(-1);
      j0 = d.tag1;
    }
    run_of[2 * order[p]] = jrun;
    if (d.tag2 < 0) continue;
    if (krun < 0 || d.tag2 != k0) {
      if (krun >= 0) added[krun] = moment++;
      krun = static_cast<int>(added.size());
      added.push_back(-1);
      k0 = d.tag2;
    }
    run_of[2 * order[p] + 1] = krun;
  }
  if (jrun >= 0) added[jrun] = moment++;
  if (krun >= 0) added[krun] = moment++;
  parmec_rank_.assign(2 * std::size_t(n), -1);
  for (int p = 0; p < n; p++)
    for (int side = 0; side < 2; side++) {
      const int r = run_of[2 * order[p] + side];
      if (r >= 0) parmec_rank_[2 * order[p] + side] = static_cast<long long>(added[r]) * n + p;
    }
}

// Atom i's contributions (local results t0..t1 and the entries received for it) added to f and torque run
// by run in Parmec's order (parmec_schedule): each run summed from its first spring on, then added.
void FixParmecSpring::add_in_parmec_order(int i, const state::LocalIncidence::Term *t0,
                                          const state::LocalIncidence::Term *t1, double *f, double *torque) const
{
  struct Item {
    long long rank;
    const double *v;  // with its sign
  };
  Item items[2 * state::OrderedSums::kMaxOrdered];
  const int cap = 2 * state::OrderedSums::kMaxOrdered;
  int n = 0;
  for (const state::LocalIncidence::Term *t = t0; t != t1 && n < cap; ++t) {
    const SpringResult &res = results_[t->r];
    items[n++] = {parmec_rank_[2 * std::size_t(t->key) + t->side], res.ft + 6 * t->side};
  }
  for (int c = 0; c < sums_.count(i) && n < cap; c++) {  // received: part2 sides, sign applied
    const double *e = sums_.entry_of(i, c);
    items[n++] = {parmec_rank_[2 * static_cast<std::size_t>(e[0]) + 1], e + 1};
  }
  std::sort(items, items + n, [](const Item &a, const Item &b) { return a.rank < b.rank; });
  const long long nspr = static_cast<long long>(defs_.size());
  double run[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int m = 0; m < n; m++) {
    const bool first = m == 0 || items[m].rank / nspr != items[m - 1].rank / nspr;
    for (int c = 0; c < 6; c++) run[c] = (first ? 0.0 : run[c]) + items[m].v[c];
    if (m + 1 < n && items[m + 1].rank / nspr == items[m].rank / nspr) continue;
    for (int c = 0; c < 3; c++) f[c] += run[c];
    if (torque)
      for (int c = 0; c < 3; c++) torque[c] += run[3 + c];
  }
}

}  // namespace dembridge
