// pair_modify timestep_check: the pair styles' own time-step check, off by default so that a LIGGGHTS deck
// prints exactly the warnings LIGGGHTS prints (LIGGGHTS checks only with fix check/timestep/gran). The
// Rayleigh and Hertz times are those of that fix (materials/timestep_estimates.h).
#include "pair_gran.h"

#include "command_args.h"
#include "timestep_estimates.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "update.h"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {
constexpr double kDefaultFraction = 0.2;  // LIGGGHTS's advice: dt below 20 % of the Rayleigh time
}

void PairGran::modify_params(int narg, char **arg)
{
  std::vector<char *> rest;
  for (int i = 0; i < narg; ++i) {
    if (std::string(arg[i]) != "timestep_check") {
      rest.push_back(arg[i]);
      continue;
    }
    if (i + 1 >= narg)
      error->all(FLERR, "pair_modify timestep_check: expected yes, no or a fraction of the Rayleigh/Hertz time in (0, 1]");
    const std::string v = arg[++i];
    const std::optional<double> f = args::number(lmp, v);
    if (v == "yes") timestep_check_ = kDefaultFraction;
    else if (v == "no" || v == "off") timestep_check_ = 0.0;
    else if (f && *f > 0.0 && *f <= 1.0) timestep_check_ = *f;
    else
      error->all(FLERR, "pair_modify timestep_check: expected yes, no or a fraction of the Rayleigh/Hertz time in (0, 1], got '" +
                            v + "'");
  }
  if (!rest.empty()) Pair::modify_params(int(rest.size()), rest.data());
}

void PairGran::setup()
{
  if (timestep_check_ <= 0.0) return;
  const property::GlobalProperty *Y = find_property("youngsModulus"), *nu = find_property("poissonsRatio");
  if (!Y || !nu || model_.dialect == gran::Dialect::LammpsNumeric)
    error->all(FLERR, "pair_style " + style_name_ +
                          ": pair_modify timestep_check needs youngsModulus and poissonsRatio (fix property/global), "
                          "which this pair style's syntax does not use");
  const double *const *v = atom->v;
  const double *r = atom->radius, *m = atom->rmass;
  const int *type = atom->type;
  double tr = 1.0e6, vmax_sqr = 0.0;
  for (int i = 0; i < atom->nlocal; ++i) {
    const int t = type[i];
    tr = std::min(tr, gran::rayleigh_time(r[i], gran::sphere_density(m[i], r[i]), Y->per_type(t), nu->per_type(t)));
    vmax_sqr = std::max(vmax_sqr, v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
  }
  double t_rayleigh = 0.0, vmax_all = 0.0;
  MPI_Allreduce(&tr, &t_rayleigh, 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(&vmax_sqr, &vmax_all, 1, MPI_DOUBLE, MPI_MAX, world);
  const double v_rel = gran::relative_speed(std::sqrt(vmax_all), 0.0);
  double th = 1.0e6;
  if (v_rel > 0.0)
    for (int i = 0; i < atom->nlocal; ++i) {
      const int t = type[i];
      const double Yeff = gran::effective_modulus(Y->per_type(t), nu->per_type(t), Y->per_type(t), nu->per_type(t));
      th = std::min(th, gran::hertz_time(r[i], gran::sphere_density(m[i], r[i]), Yeff, v_rel));
    }
  double t_hertz = 0.0;
  MPI_Allreduce(&th, &t_hertz, 1, MPI_DOUBLE, MPI_MIN, world);
  if (comm->me != 0) return;
  const double dt = update->dt;
  auto warn = [&](const char *what, double t) {
    if (dt <= timestep_check_ * t) return;
    error->warning(FLERR, fmt::format("pair_style {}: the time step {:.6g} is {:.6g} % of the {} time {:.6g} of the particles "
                                      "(pair_modify timestep_check {:g}): contacts may blow up; use a time step below {:.6g}",
                                      style_name_, dt, 100.0 * dt / t, what, t, timestep_check_, timestep_check_ * t));
  };
  warn("Rayleigh", t_rayleigh);
  if (v_rel > 0.0) warn("Hertz", t_hertz);
}

}  // namespace dembridge
