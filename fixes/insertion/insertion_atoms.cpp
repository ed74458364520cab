#include "insertion_atoms.h"

#include "fix_property_atom_liggghts.h"

#include "atom.h"
#include "lammps_atom_vec.h"
#include "comm.h"
#include "compute.h"
#include "domain.h"
#include "error.h"
#include "modify.h"
#include "region.h"

#include <algorithm>
#include <cmath>
#include <mpi.h>
#include <utility>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {
std::vector<double> allgather(LAMMPS *lmp, const std::vector<double> &mine)
{
  const int nprocs = lmp->comm->nprocs;
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, lmp->world);
  for (int p = 1; p < nprocs; ++p) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> all(displs[nprocs - 1] + counts[nprocs - 1]);
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, lmp->world);
  return all;
}

// A point belongs to exactly one rank of the processor grid (points beyond the box go to the edge ranks).
bool owns(LAMMPS *lmp, const double *x)
{
  Domain *d = lmp->domain;
  Comm *c = lmp->comm;
  for (int k = 0; k < 3; ++k) {
    if (x[k] < d->sublo[k] && c->myloc[k] != 0) return false;
    if (x[k] >= d->subhi[k] && c->myloc[k] != c->procgrid[k] - 1) return false;
  }
  return true;
}
// The temperature computes count their degrees of freedom at setup, when an insertion deck has no atoms yet
// (0 dof, so temp and ke stay 0 without compute_modify ... dynamic/dof yes): tell them the count changed,
// as LIGGGHTS's thermo (its ke is the sum of m v^2 / 2) never needs. Collective: every rank inserts together.
void recount_temperature_dof(LAMMPS *lmp)
{
  for (Compute *c : lmp->modify->get_compute_list())
    if (c->tempflag) c->setup();
}
}  // namespace

RegionContent region_content(LAMMPS *lmp, Region *region)
{
  Atom *atom = lmp->atom;
  std::vector<double> mine;  // tag, r, m
  for (int i = 0; i < atom->nlocal; ++i)
    if (region->match(atom->x[i][0], atom->x[i][1], atom->x[i][2]))
      mine.insert(mine.end(), {static_cast<double>(atom->tag[i]), atom->radius[i], atom->rmass[i]});
  const std::vector<double> all = allgather(lmp, mine);
  std::vector<std::pair<double, int>> order;
  for (size_t k = 0; k < all.size(); k += 3) order.emplace_back(all[k], static_cast<int>(k));
  std::sort(order.begin(), order.end());
  RegionContent c;
  const double four_pi_3 = 4. * 3.14159265358979323846 / 3.;
  for (const auto &o : order) {
    const double r = all[o.second + 1];
    c.count++;
    c.volume += four_pi_3 * r * r * r;
    c.mass += all[o.second + 2];
  }
  return c;
}

std::vector<double> gather_spheres_near(LAMMPS *lmp, const double *lo, const double *hi, double reach)
{
  Atom *atom = lmp->atom;
  std::vector<double> mine;
  for (int i = 0; i < atom->nlocal; ++i) {
    double x[3] = {atom->x[i][0], atom->x[i][1], atom->x[i][2]};
    lmp->domain->remap(x);
    const double cut = reach + atom->radius[i];
    if (x[0] < lo[0] - cut || x[0] > hi[0] + cut || x[1] < lo[1] - cut || x[1] > hi[1] + cut || x[2] < lo[2] - cut ||
        x[2] > hi[2] + cut)
      continue;
    mine.insert(mine.end(), {x[0], x[1], x[2], atom->radius[i]});
  }
  return allgather(lmp, mine);
}

SetProperty find_set_property(LAMMPS *lmp, const std::string &name, double value, const std::string &who)
{
  if (name.empty()) return {};
  FixPropertyAtomLiggghts *f = FixPropertyAtomLiggghts::find(lmp, name);
  if (!f || !f->is_scalar())
    lmp->error->all(FLERR, who + "set_property: '" + name + "' is not a scalar fix property/atom (define it before, with "
                                 "'fix ID all property/atom " + name + " scalar yes no no DEFAULT')");
  return {f, value};
}

bigint create_spheres(LAMMPS *lmp, const std::vector<NewSphere> &all, const SetProperty &set)
{
  Atom *atom = lmp->atom;
  if (lmp->comm->layout == Comm::LAYOUT_TILED)
    lmp->error->all(FLERR, "Fix insert/*: comm_style tiled is not supported (use the brick layout)");
  tagint maxtag = 0, maxtag_all = 0;
  for (int i = 0; i < atom->nlocal; ++i) maxtag = std::max(maxtag, atom->tag[i]);
  MPI_Allreduce(&maxtag, &maxtag_all, 1, MPI_LMP_TAGINT, MPI_MAX, lmp->world);
  for (size_t k = 0; k < all.size(); ++k) {
    const NewSphere &s = all[k];
    if (!owns(lmp, s.x)) continue;
    double x[3] = {s.x[0], s.x[1], s.x[2]};
    atom->avec->create_atom(s.type, x);
    const int m = atom->nlocal - 1;
    atom->tag[m] = maxtag_all + 1 + static_cast<tagint>(k);
    atom->mask[m] = 1 | s.groupbit;
    for (int d = 0; d < 3; ++d) {
      atom->v[m][d] = s.v[d];
      atom->omega[m][d] = s.omega[d];
    }
    atom->radius[m] = s.radius;
    atom->rmass[m] = s.mass;
    lmp->modify->create_attribute(m);
    if (set.fix) set.fix->values()[m] = set.value;  // overrides the property's default, as LIGGGHTS
  }
  const bigint n = static_cast<bigint>(all.size());
  if (n > 0) {
    atom->natoms += n;
    if (atom->map_style != Atom::MAP_NONE) {
      atom->nghost = 0;
      atom->map_init();
      atom->map_set();
    }
    recount_temperature_dof(lmp);
  }
  return n;
}

}  // namespace dembridge
