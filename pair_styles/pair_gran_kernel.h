// The neighbour loop of the dembridge granular pair styles, free of LAMMPS headers: the plain
// arrays of one compute() go in (PairLoopData), each contact goes out to the caller's sink (the
// serial style adds it to the atoms, the /omp style stores it for its ordered gather). The loop is
// compiled per model so that no per-contact switch is left on the model (issue 12, P1/P2).
#pragma once

#include "contact_law.h"
#include "touch_flag.h"

#include <cstddef>

namespace dembridge::gran {

// Everything the loop reads, resolved once per compute(). Per-atom vectors are flat (x[3*i+k]):
// LAMMPS allocates its 2-d per-atom arrays as one contiguous block.
struct PairLoopData {
  const double *x = nullptr, *v = nullptr, *omega = nullptr;
  const double *radius = nullptr, *rmass = nullptr;
  const int *type = nullptr, *mask = nullptr;
  const double *mass_rigid = nullptr;  // body masses (0: not in a body), null without fix rigid
  int freeze_groupbit = 0;
  int nlocal = 0;
  bool newton_pair = false;
  // half neighbour list
  const int *ilist = nullptr, *numneigh = nullptr;
  int *const *firstneigh = nullptr;
  int neighmask = 0;
  // history in neighbour-list order (null when the model has none): the jj-th neighbour of
  // atom i owns values hist[(hist_first[i] + jj) * nv ...] and flag touch[hist_first[i] + jj]
  double *hist = nullptr;
  TouchFlag *touch = nullptr;
  const std::size_t *hist_first = nullptr;
  int nv = 0;
  bool history_update = true;   // false in the setup pass: springs frozen
  bool clear_separated = true;  // false: 3.8 keeps a separated pair's springs until a rebuild
  double dt = 0.0;
  const PairCoeffs *coeffs = nullptr;  // coeffs[itype * coeff_stride + jtype]
  int coeff_stride = 0;
  bool uniform_coeffs = false;  // every type pair has coeffs[coeff_stride + 1] (MaterialTable::uniform)
  int max_type = 0;
  const ContactLaw *law = nullptr;
  enum class Scan { Default, Avx2, Scalar } scan = Scan::Default;  // a forced loop (the pair-loop probe)
};

// Why a loop stopped early (the caller reports it with the LAMMPS error it wants).
struct PairLoopError {
  enum Kind { None, TypeAfterInit, Coincident, NoFiniteMass } kind = None;
  int i = -1, j = -1;
};

// Evaluates the contacts of ilist[ii_begin .. ii_end), in list order, updating their history, and
// hands each to sink(i, j, ii, jj, const ContactResult &). Disjoint ii ranges may run on threads:
// each i writes only its own history slots. Dispatches once per call to the loop compiled for
// d.law's model (LAMMPS laws: hooke/hertz x history x limit_damping; LIGGGHTS laws: normal x
// tangential model). Entry point for the serial and the /omp styles (pairperf-kernel note).
template <class Sink> PairLoopError run_pair_loop(const PairLoopData &d, int ii_begin, int ii_end, Sink &&sink);

}  // namespace dembridge::gran

#include "pair_gran_loop.h"
