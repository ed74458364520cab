#include "fix_heat_gran.h"

#include "fix_property_atom_liggghts.h"
#include "fix_property_global.h"
#include "heat_conduction.h"
#include "mesh_args.h"
#include "pair_gran.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "neigh_list.h"
#include "style_registry.h"
#include "update.h"
#include "utils.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace dembridge {

FixHeatGran::FixHeatGran(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const std::string cmd = std::string("fix ") + id + " " + style;
  if (!atom->radius_flag || !atom->rmass_flag)
    error->all(FLERR, cmd + ": needs per-particle radius and mass (atom_style sphere or granular)");
  MeshArgs a(lmp, cmd, narg, arg, 3);
  a.expect_keyword("initial_temperature", "initial_temperature T0 [contact_area overlap|projection|constant A]");
  T0_ = heat::liggghts_initial_temperature(a.number("initial_temperature"));
  while (!a.done()) {
    const std::string key = a.word("keyword");
    if (key == "contact_area") {
      const std::string mode = a.word("contact_area");
      if (mode == "overlap") area_ = Area::Overlap;
      else if (mode == "projection") area_ = Area::Projection;
      else if (mode == "constant") {
        area_ = Area::Constant;
        constant_area_ = a.positive("contact_area constant");
      } else
        a.fail("contact_area", "expected overlap, projection or constant A, got '" + mode + "'");
    } else if (key == "area_correction") {
      a.fail("area_correction", "not implemented (it needs youngsModulusOriginal); leave it out");
    } else {
      a.fail("'" + key + "'", "unknown keyword (expected contact_area)");
    }
  }
  scalar_flag = 1;
  global_freq = 1;
  extscalar = 1;
  peratom_flag = 1;
  size_peratom_cols = 0;
  peratom_freq = 1;
  time_depend = 1;
}

// As in LIGGGHTS, the three properties are (re)defined here: a property/atom Temp defined before starts
// again from T0; set their values after this fix (set ... d_Temp V).
void FixHeatGran::post_constructor()
{
  char t0[64];
  std::snprintf(t0, sizeof t0, "%.17g", T0_);
  modify->add_fix(std::string("Temp all property/atom Temp scalar yes yes no ") + t0);
  modify->add_fix("heatFlux all property/atom heatFlux scalar yes no yes 0.");
  modify->add_fix("heatSource all property/atom heatSource scalar yes yes no 0.");
  find_properties();
}

void FixHeatGran::find_properties()
{
  temp_ = FixPropertyAtomLiggghts::find(lmp, "Temp");
  flux_ = FixPropertyAtomLiggghts::find(lmp, "heatFlux");
  source_ = FixPropertyAtomLiggghts::find(lmp, "heatSource");
  if (!temp_ || !flux_ || !source_ || !temp_->is_scalar() || !flux_->is_scalar() || !source_->is_scalar())
    error->all(FLERR, std::string("fix ") + id + " " + style +
                          ": the per-atom properties Temp, heatFlux and heatSource (fix property/atom NAME scalar ...) are missing");
}

int FixHeatGran::setmask() { return INITIAL_INTEGRATE | POST_FORCE | FINAL_INTEGRATE; }

std::vector<double> FixHeatGran::per_type(const char *name, int max_type)
{
  const std::string caller = std::string("fix ") + id + " " + style;
  const property::GlobalProperty *p = FixPropertyGlobal::find(lmp, name);
  if (!p) error->all(FLERR, property::missing_property_message(name, caller));
  try {
    p->require(property::Kind::PerType, max_type, caller);
  } catch (const std::exception &e) {
    error->all(FLERR, e.what());
  }
  std::vector<double> v(max_type + 1, 0.0);
  for (int t = 1; t <= max_type; ++t) v[t] = p->per_type(t);
  return v;
}

void FixHeatGran::init()
{
  const std::string cmd = std::string("fix ") + id + " " + style;
  if (modify->get_fix_by_style("^heat/gran").size() > 1) error->all(FLERR, cmd + ": only one fix heat/gran is allowed");
  pair_ = dynamic_cast<PairGran *>(force->pair);
  if (!pair_) error->all(FLERR, cmd + ": needs a granular pair style of this plugin (pair_style gran ...)");
  find_properties();
  const int max_type = atom->ntypes;
  conductivity_ = per_type("thermalConductivity", max_type);
  capacity_ = per_type("thermalCapacity", max_type);
  for (int t = 1; t <= max_type; ++t)
    if (conductivity_[t] < 0.0)
      error->all(FLERR, cmd + ": thermalConductivity of type " + std::to_string(t) + " is < 0");
}

// LIGGGHTS computes no flux at setup: the first dump shows heatFlux 0.
void FixHeatGran::setup(int) { temp_->forward_comm(); }

void FixHeatGran::initial_integrate(int)
{
  double *q = flux_->values();
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; ++i)
    if (mask[i] & groupbit) q[i] = 0.0;
  temp_->forward_comm();
}

void FixHeatGran::post_force(int)
{
  const NeighList *list = pair_->neighbor_list();
  const double *const *x = atom->x;
  const double *radius = atom->radius;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const bool newton = force->newton_pair != 0;
  const double *T = temp_->values();
  double *q = flux_->values();
  if (newton) std::fill(q + nlocal, q + nlocal + atom->nghost, 0.0);

  for (int ii = 0; ii < list->inum; ++ii) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; ++jj) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!(mask[i] & groupbit) && !(mask[j] & groupbit)) continue;
      const double delx = x[i][0] - x[j][0], dely = x[i][1] - x[j][1], delz = x[i][2] - x[j][2];
      const double rsq = delx * delx + dely * dely + delz * delz;
      const double radsum = radius[i] + radius[j];
      if (rsq >= radsum * radsum) continue;
      double area = constant_area_;
      if (area_ == Area::Overlap) area = heat::overlap_contact_area(std::sqrt(rsq), radius[i], radius[j]);
      else if (area_ == Area::Projection) {
        const double rmax = std::max(radius[i], radius[j]);
        area = M_PI * rmax * rmax;
      }
      const double flux = (T[j] - T[i]) * heat::contact_conductance(conductivity_[type[i]], conductivity_[type[j]], area);
      q[i] += flux;
      if (newton || j < nlocal) q[j] -= flux;
    }
  }
  if (newton) flux_->reverse_comm();
}

void FixHeatGran::final_integrate()
{
  double *T = temp_->values();
  const double *q = flux_->values();
  source_->forward_comm();
  const double *s = source_->values();
  const double *m = atom->rmass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const double dt = update->dt;
  for (int i = 0; i < atom->nlocal; ++i)
    if (mask[i] & groupbit) T[i] = heat::updated_temperature(T[i], q[i], s[i], dt, m[i], capacity_[type[i]]);
}

double FixHeatGran::compute_scalar()
{
  const double *T = temp_->values();
  const double *m = atom->rmass;
  const int *type = atom->type;
  double sum = 0.0;
  for (int i = 0; i < atom->nlocal; ++i) sum += capacity_[type[i]] * m[i] * T[i];
  double all = 0.0;
  MPI_Allreduce(&sum, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

static RegisterStyle reg_heat_gran("fix", "heat/gran", "LIGGGHTS heat conduction between touching particles",
                                   create_fix<FixHeatGran>);
static RegisterStyle reg_heat_gran_cond("fix", "heat/gran/conduction", "LIGGGHTS heat conduction (alias of heat/gran)",
                                        create_fix<FixHeatGran>);

}  // namespace dembridge
