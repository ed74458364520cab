// The plugin's styles under `-sf omp` / `suffix omp`. LAMMPS looks for "STYLE/omp" first, and its
// built-in gran/hooke/omp, gran/hooke/history/omp and gran/hertz/history/omp know neither the
// LIGGGHTS syntax nor our contact history; registering these names makes the suffix run ours.
// They are the same PairGran (not threaded yet: one thread computes, results equal the un-suffixed
// style for any thread count).
#include "pair_gran.h"
#include "style_registry.h"

namespace dembridge {

template <const char *Base> static void *create_pair_omp(void *lmp)
{
  return new PairGran(static_cast<LAMMPS_NS::LAMMPS *>(lmp), Base);
}

#define DEMBRIDGE_PAIR_OMP(var, base)  \
  static constexpr char var[] = base; \
  static RegisterStyle reg_omp_##var("pair", base "/omp", "dembridge " base " under the omp suffix", create_pair_omp<var>)

DEMBRIDGE_PAIR_OMP(kOmpGranHooke, "gran/hooke");
DEMBRIDGE_PAIR_OMP(kOmpGranHookeHistory, "gran/hooke/history");
DEMBRIDGE_PAIR_OMP(kOmpGranHertzHistory, "gran/hertz/history");

}  // namespace dembridge
