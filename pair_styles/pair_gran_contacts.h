// PairGran's neighbour loop (see for_each_contact in pair_gran.h): the serial compute and the
// threaded /omp compute both run it and differ only in what they do with each contact.
#pragma once

#include "pair_gran.h"

#include "fix_contact_history.h"

#include "atom.h"
#include "error.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <string>

namespace dembridge {

// Centre distances below 1e-12 of the radius sum count as coincident (squared here).
inline constexpr double kCoincidentCentres = 1e-24;

template <class Sink> void PairGran::for_each_contact(int ii_from, int ii_to, Sink &&sink)
{
  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  const double *radius = atom->radius, *rmass = atom->rmass;
  const int *type = atom->type, *mask = atom->mask;
  const double dt = update->dt;
  const bool history_update = !update->setupflag;
  const int max_type = table_.max_type();
  const int nv = model_.contact.history_size();
  const bool stale_springs = model_.contact.stale_springs_until_rebuild;
  const bool rebuilt = neighbor->ago == 0;
  const int *ilist = list->ilist, *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  const double *mass_rigid = fix_rigid_ ? mass_rigid_.data() : nullptr;

  gran::ContactResult res{};
  double scratch[6] = {0, 0, 0, 0, 0, 0};
  for (int ii = ii_from; ii < ii_to; ii++) {
    const int i = ilist[ii];
    const int itype = type[i];
    if (itype > max_type)
      error->one(FLERR, "pair_style " + style_name_ + ": atom type " + std::to_string(itype) +
                            " appeared after init; the material table only covers types up to " + std::to_string(max_type));
    const bool ifrozen = mask[i] & freeze_groupbit_;
    const double mi = (mass_rigid && mass_rigid[i] > 0.0) ? mass_rigid[i] : rmass[i];
    const gran::SphereView a{x[i], v[i], omega[i], radius[i], mi};
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    // per-atom bases of the list-order history and of the coefficient row, hoisted out of the pair loop
    double *hist_i = history_ && jnum ? history_->slot(i, 0) : nullptr;
    unsigned char *touch_i = history_ && jnum ? &history_->touched(i, 0) : nullptr;
    const gran::PairCoeffs *coeff_row = &table_.at(itype, 0);
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      // cheap overlap test first: most neighbour entries are not in contact (the law repeats
      // the same arithmetic, so both agree exactly)
      const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
      const double radsum = radius[i] + radius[j];
      if (dx * dx + dy * dy + dz * dz >= radsum * radsum) {
        // 2.x and LAMMPS: the springs vanish on separation. 3.8 clears them only on a neighbour
        // rebuild step: until then a separated pair keeps them (kept 'touched', so a rebuild
        // carries them) and a contact resuming meanwhile continues with the old springs.
        if (touch_i && touch_i[jj] && (!stale_springs || rebuilt)) {
          touch_i[jj] = 0;  // the fix drops untouched springs at the next neighbour rebuild
          for (int k = 0; k < nv; k++) hist_i[jj * nv + k] = 0.0;
        }
        continue;
      }
      // coincident centres leave the contact normal undefined (the built-ins return NaN)
      if (!(dx * dx + dy * dy + dz * dz > kCoincidentCentres * radsum * radsum)) degenerate_contact(i, j, true);
      double *hist = hist_i ? hist_i + jj * nv : scratch;
      const double mj = (mass_rigid && mass_rigid[j] > 0.0) ? mass_rigid[j] : rmass[j];
      const gran::SphereView b{x[j], v[j], omega[j], radius[j], mj};
      double meff = mi * mj / (mi + mj);
      if (ifrozen) meff = mj;
      if (mask[j] & freeze_groupbit_) meff = mi;
      if (!std::isfinite(meff)) degenerate_contact(i, j, false);
      law_.evaluate(a, b, meff, coeff_row[type[j]], hist, history_update, dt, res);
      if (touch_i) touch_i[jj] = 1;
      sink(i, j, ii, jj, res);
    }
  }
}

}  // namespace dembridge
