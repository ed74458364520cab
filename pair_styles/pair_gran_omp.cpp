#include "pair_gran_omp.h"

#include "pair_gran_contacts.h"
#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "neighbor.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>

#if defined(_OPENMP)
#include <omp.h>
#endif

using namespace LAMMPS_NS;

namespace dembridge {

// Atom ranges the first blocks are resolved in, shared among the threads. Results do not depend on it.
static constexpr int kResolveChunks = 64;
// Cost of a touching pair relative to a neighbour entry that is not touching (block balance only):
// the value that splits the pair loop's instructions evenly on the chute (callgrind per thread, 2
// threads, 120 steps: 8 left the second block 3.3 % heavier, 5 the first 0.3 %).
static constexpr double kContactCost = 5.25;

PairGranOMP::PairGranOMP(LAMMPS *lmp, const char *base_style) : PairGran(lmp, base_style) {}

// The threaded compute's sink: block b's contacts through the gather (kept for the virial on tally steps).
struct PairGranOMP::GatherSink {
  threads::PairForceGather &gather;
  int b;
  bool keep_all;
  double *f, *torque;
  void operator()(int i, int j, int ii, int jj, const gran::ContactResult &res) const
  {
    gather.add(b, i, j, res.F, res.Ti, res.Tj, f, torque);
    if (keep_all) gather.keep(gather.first_pair(ii) + std::size_t(jj), res.F);
  }
  // the AVX2 loop fetches atom j's rows a few pairs ahead, as for the serial compute's sink
  void prefetch(int j) const
  {
    __builtin_prefetch(f + 3 * std::size_t(j), 1);
    __builtin_prefetch(torque + 3 * std::size_t(j), 1);
  }
};

int PairGranOMP::requested_threads() const
{
#if defined(_OPENMP)
  return std::max(1, comm->nthreads);  // set by `package omp N` (and -pk omp N; -sf omp alone: OMP_NUM_THREADS)
#else
  return 1;
#endif
}

void PairGranOMP::init_style()
{
  PairGran::init_style();
#if !defined(_OPENMP)
  if (comm->nthreads > 1 && comm->me == 0)
    error->warning(FLERR, "pair_style " + style_name() + "/omp: the dembridge plugin was built without OpenMP; using 1 thread");
#endif
  report_threads_ = true;
}

void PairGranOMP::compute(int eflag, int vflag)
{
  const int nthreads = requested_threads();
  if (nthreads == 1) {  // the serial loop itself: nothing to gather
    PairGran::compute(eflag, vflag);
    threads_used_ = 1;
    report_threads();
    return;
  }
  ev_init(eflag, vflag);
  if (!force_on()) return;
  begin_contacts();
  if (list->inum == 0) return end_contacts();  // (no per-atom arrays to point at)
  const int nreceive = force->newton_pair ? atom->nlocal + atom->nghost : atom->nlocal;
  index_list(nreceive, nthreads);

  double *f = atom->f[0], *torque = atom->torque[0];
  const bool keep_all = evflag;  // the virial tally walks every contact afterwards
  const int nblocks = gather_.nblocks();
  std::exception_ptr failure;
  std::mutex failure_lock;
  std::atomic<bool> failed{false};
  std::atomic<int> used{0};
#if defined(_OPENMP)
#pragma omp parallel num_threads(nthreads)
#endif
  {
    used++;
#if defined(_OPENMP)
    const int tid = omp_get_thread_num(), nt = omp_get_num_threads();
#else
    const int tid = 0, nt = 1;
#endif
    // pass 1: each block's rows in order by one thread; atoms an earlier block names are deferred
    for (int b = tid; b < nblocks; b += nt) {
      try {
        gather_.begin_block(b, keep_all);
        for_each_contact(gather_.block_begin(b), gather_.block_begin(b + 1), GatherSink{gather_, b, keep_all, f, torque});
      } catch (...) {  // no exception may leave the parallel region; the error is raised after it
        std::lock_guard<std::mutex> hold(failure_lock);
        if (!failure) failure = std::current_exception();
        failed = true;
      }
    }
#if defined(_OPENMP)
#pragma omp barrier
#endif
    // pass 2: the deferred terms, after the earlier blocks' own additions (the serial order)
    if (!failed) gather_.apply_deferred(tid, nt, f, torque);
  }
  if (failure) std::rethrow_exception(failure);
  threads_used_ = used;
  if (evflag) tally_virial();
  end_contacts();
  report_threads();
}

// The gather index follows the neighbour list: rebuilt whenever LAMMPS rebuilt the lists.
void PairGranOMP::index_list(int nreceive, int nblocks)
{
  if (gather_build_ == neighbor->ncalls && gather_.nreceive() == nreceive && gather_.inum() == list->inum &&
      gather_.nblocks() == nblocks)
    return;
  // Blocks of equal expected work: a touching pair costs the contact law, about kContactCost
  // times an entry that fails the overlap test (callgrind, chute). Touching now is a good guess
  // until the next rebuild; a poor guess only slows, never changes, the result.
  double **x = atom->x;
  const double *radius = atom->radius;
  const int inum = list->inum;
  const int *ilist = list->ilist, *numneigh = list->numneigh;
  int *const *firstneigh = list->firstneigh;
  row_weight_.resize(std::size_t(std::max(0, inum)));
#if defined(_OPENMP)
#pragma omp parallel num_threads(nblocks)
#endif
  {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int ii = 0; ii < inum; ii++) {
      const int i = ilist[ii];
      const int *jlist = firstneigh[i];
      int touching = 0;
      for (int jj = 0; jj < numneigh[i]; jj++) {
        const int j = jlist[jj] & NEIGHMASK;
        const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
        const double radsum = radius[i] + radius[j];
        touching += dx * dx + dy * dy + dz * dz < radsum * radsum;
      }
      row_weight_[ii] = numneigh[i] + kContactCost * touching;
    }
#if defined(_OPENMP)
#pragma omp single
#endif
    gather_.index(inum, ilist, numneigh, nreceive, nblocks, row_weight_.data());
#if defined(_OPENMP)
#pragma omp for schedule(static, 1)
#endif
    for (int b = 0; b < gather_.nblocks(); b++) gather_.mark_block(b, ilist, numneigh, firstneigh, NEIGHMASK);
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int c = 0; c < kResolveChunks; c++)
      gather_.resolve(int(std::int64_t(nreceive) * c / kResolveChunks), int(std::int64_t(nreceive) * (c + 1) / kResolveChunks));
  }
  gather_build_ = neighbor->ncalls;
}

// Energy/virial tallies in the serial loop's order, from the stored contacts (thermo steps only).
void PairGranOMP::tally_virial()
{
  double **x = atom->x;
  const int nlocal = atom->nlocal, newton_pair = force->newton_pair;
  const int *ilist = list->ilist, *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = ilist[ii];
    const std::size_t p0 = gather_.first_pair(ii);
    for (int jj = 0; jj < numneigh[i]; jj++) {
      if (!gather_.kept(p0 + jj)) continue;
      const int j = firstneigh[i][jj] & NEIGHMASK;
      const double *F = gather_.kept_force(p0 + jj);
      ev_tally_xyz(i, j, nlocal, newton_pair, 0.0, 0.0, F[0], F[1], F[2], x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]);
    }
  }
}

void PairGranOMP::report_threads()
{
  if (!report_threads_) return;
  report_threads_ = false;
  if (comm->me == 0)
    utils::logmesg(lmp, "dembridge pair_style {}/omp: {} OpenMP thread(s) per MPI task in the pair compute{}\n", style_name(),
                   threads_used_, threads_used_ > 1 ? " (forces gathered in the serial order: identical to 1 thread)" : "");
}

void *PairGranOMP::extract(const char *name, int &dim)
{
  dim = 0;
  if (std::string(name) == "nthreads") return &threads_used_;
  return PairGran::extract(name, dim);
}

double PairGranOMP::memory_usage()
{
  return PairGran::memory_usage() + double(gather_.memory_bytes());
}

// One /omp creator per style name.
template <const char *Base> static void *create_pair_omp(void *lmp)
{
  return new PairGranOMP(static_cast<LAMMPS *>(lmp), Base);
}

#define DEMBRIDGE_PAIR_OMP(var, base)  \
  static constexpr char var[] = base; \
  static RegisterStyle reg_omp_##var("pair", base "/omp", "dembridge " base ", threaded (package omp)", create_pair_omp<var>)

DEMBRIDGE_PAIR_OMP(kOmpGranHooke, "gran/hooke");
DEMBRIDGE_PAIR_OMP(kOmpGranHookeHistory, "gran/hooke/history");
DEMBRIDGE_PAIR_OMP(kOmpGranHertzHistory, "gran/hertz/history");
DEMBRIDGE_PAIR_OMP(kOmpGranHookeStiffness, "gran/hooke/stiffness");
DEMBRIDGE_PAIR_OMP(kOmpGranHookeHistoryStiffness, "gran/hooke/history/stiffness");
DEMBRIDGE_PAIR_OMP(kOmpGranHertzHistoryStiffness, "gran/hertz/history/stiffness");
DEMBRIDGE_PAIR_OMP(kOmpGranHookeHistorySimple, "gran/hooke/history/simple");
DEMBRIDGE_PAIR_OMP(kOmpGranHertzHistorySimple, "gran/hertz/history/simple");
DEMBRIDGE_PAIR_OMP(kOmpGran, "gran");

}  // namespace dembridge
