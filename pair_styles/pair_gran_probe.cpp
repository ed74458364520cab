// The opt-in pair-loop probe of PairGran (pair_gran.h; bench/run_pair_probe.py): DEMBRIDGE_PAIR_PROBE=STEP[,PASSES]
// reruns STEP's neighbour loop PASSES times with each loop (AVX2, scalar) and prints their thread CPU times.
// Kept apart from the pair style: a run without the variable only compares the step number once per compute.
#include "pair_gran.h"

#include "fix_contact_history.h"

#include "atom.h"
#include "update.h"

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

namespace dembridge {

void PairGran::read_probe_setting()
{
  if (const char *probe = std::getenv("DEMBRIDGE_PAIR_PROBE")) {  // STEP[,PASSES]
    const std::string text(probe);
    const std::size_t comma = text.find(',');
    probe_step_ = utils::bnumeric(FLERR, text.substr(0, comma), false, lmp);
    if (comma != std::string::npos) probe_passes_ = std::max(1, utils::inumeric(FLERR, text.substr(comma + 1), false, lmp));
  }
}

// This step's loop, PASSES times per loop, the loops alternating (which goes first alternates too), each
// pass from the same history, forces into scratch arrays.
void PairGran::probe_pair_loop()
{
  using Scan = gran::PairLoopData::Scan;
  const std::size_t nslot = history_ ? history_->slot_count() : 0, nval = history_ ? nslot * history_->nvalues() : 0;
  const std::vector<double> hist0(history_ ? history_->values() : nullptr, history_ ? history_->values() + nval : nullptr);
  const std::vector<gran::TouchFlag> touch0(history_ ? history_->touch_flags() : nullptr, history_ ? history_->touch_flags() + nslot : nullptr);
  std::vector<double> f(3 * std::size_t(atom->nmax)), torque(f.size());
  const int evflag_run = evflag;
  evflag = 0;
  std::vector<double> t[2];  // CPU seconds per pass: AVX2, scalar
  std::vector<double> evict(std::size_t(1) << 19);  // 4 MB
  for (int pass = 0; pass < 2 * probe_passes_; pass++) {
    const int which = (pass + pass / 2) % 2;  // avx2 scalar, scalar avx2, ...
    if (history_) {
      std::copy(hist0.begin(), hist0.end(), history_->values());
      std::copy(touch0.begin(), touch0.end(), history_->touch_flags());
    }
    // the run's other work passes over every per-atom array between two pair computes: evict the
    // copies above from the core's L2 (1 MB here) as that would, so the pass starts from L3 as in a run
    for (std::size_t k = 0; k < evict.size(); k += 8) evict[k] += 1.0;
    forced_scan_ = which == 0 ? Scan::Avx2 : Scan::Scalar;
    timespec t0{}, t1{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    serial_contacts(f.data(), torque.data());
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    t[which].push_back(double(t1.tv_sec - t0.tv_sec) + 1e-9 * double(t1.tv_nsec - t0.tv_nsec));
  }
  forced_scan_ = Scan::Default;
  evflag = evflag_run;
  if (history_) {
    std::copy(hist0.begin(), hist0.end(), history_->values());
    std::copy(touch0.begin(), touch0.end(), history_->touch_flags());
  }
  std::vector<double> ratio(t[0].size());
  for (std::size_t k = 0; k < ratio.size(); k++) ratio[k] = t[0][k] / t[1][k];
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  const double min0 = *std::min_element(t[0].begin(), t[0].end()), min1 = *std::min_element(t[1].begin(), t[1].end());
  utils::logmesg(lmp, "DEMBRIDGE_PAIR_PROBE step {} passes {} avx2 min {:.1f} median {:.1f} us scalar min {:.1f} median {:.1f} us "
                      "ratio of min {:.4f} median of ratios {:.4f}\n",
                 update->ntimestep, probe_passes_, 1e6 * min0, 1e6 * median(t[0]), 1e6 * min1, 1e6 * median(t[1]), min0 / min1, median(ratio));
}

}  // namespace dembridge
