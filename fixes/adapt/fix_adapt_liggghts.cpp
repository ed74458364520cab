#include "fix_adapt_liggghts.h"
#include "command_args.h"

#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "input.h"
#include "modify.h"
#include "update.h"
#include "utils.h"
#include "variable.h"

#include <climits>
#include <cmath>
#include <optional>
#include <cstring>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {
constexpr double kPi = 3.14159265358979323846;  // LIGGGHTS's MY_PI
}

bool FixAdaptLiggghts::is_liggghts_form(LAMMPS *lmp, int narg, char **arg)
{
  if (narg < 7 || std::strcmp(arg[4], "atom") != 0 || std::strcmp(arg[5], "diameter") != 0) return false;
  if (std::strncmp(arg[6], "v_", 2) != 0) return false;
  const int ivar = lmp->input->variable->find(arg[6] + 2);
  if (ivar < 0 || !lmp->input->variable->atomstyle(ivar)) return false;
  for (int k = 7; k < narg; ++k)
    if (std::strcmp(arg[k], "atom") == 0 || std::strcmp(arg[k], "pair") == 0 || std::strcmp(arg[k], "kspace") == 0 ||
        std::strcmp(arg[k], "bond") == 0 || std::strcmp(arg[k], "angle") == 0)
      return false;  // more adaptations: LAMMPS's fix adapt
  return true;
}

FixAdaptLiggghts::FixAdaptLiggghts(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const std::string caller = std::string("fix adapt (id ") + id + ")";
  const std::optional<long long> n = args::integer(lmp, arg[3]);
  if (!n || *n < 0 || *n > INT_MAX) error->all(FLERR, caller + ": N = " + arg[3] + ": expected a step interval >= 0");
  nevery = int(*n);
  variable_ = arg[6] + 2;
  for (int k = 7; k < narg; k += 2) {
    const std::string key = arg[k];
    if (k + 1 >= narg) error->all(FLERR, caller + ": keyword '" + key + "' needs a value");
    const std::string value = arg[k + 1];
    // LIGGGHTS accepts reset and scale; neither changes an atom diameter (its restore does nothing for atoms)
    if ((key == "reset" || key == "scale") && (value == "yes" || value == "no")) continue;
    error->all(FLERR, caller + ": keyword '" + key + " " + value + "': expected reset yes|no or scale yes|no");
  }
  if (!atom->radius_flag || !atom->rmass_flag)
    error->all(FLERR, caller + ": atom diameter needs per-atom radius and mass (atom_style sphere)");
  comm_forward = 2;
  // Not 'adapt': LAMMPS's atom_style sphere takes every fix of that style name for its own FixAdapt.
  delete[] style;
  style = utils::strdup("adapt/liggghts");
}

int FixAdaptLiggghts::setmask() { return FixConst::PRE_FORCE; }

void FixAdaptLiggghts::init()
{
  ivar_ = input->variable->find(variable_.c_str());
  if (ivar_ < 0) error->all(FLERR, std::string("fix adapt (id ") + id + "): no variable named '" + variable_ + "'");
  if (!input->variable->atomstyle(ivar_))
    error->all(FLERR, std::string("fix adapt (id ") + id + "): variable '" + variable_ + "' is no longer atom-style");
}

void FixAdaptLiggghts::setup_pre_force(int) { change_diameters(); }

void FixAdaptLiggghts::pre_force(int)
{
  if (nevery == 0 || update->ntimestep % nevery) return;
  change_diameters();
}

void FixAdaptLiggghts::change_diameters()
{
  modify->clearstep_compute();  // the variable may invoke computes
  const int nlocal = atom->nlocal;
  diameters_.assign(nlocal > 0 ? nlocal : 1, 0.0);
  input->variable->compute_atom(ivar_, igroup, diameters_.data(), 1, 0);
  double *radius = atom->radius, *rmass = atom->rmass;
  for (int i = 0; i < nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double density = rmass[i] / (4.0 * kPi / 3.0 * radius[i] * radius[i] * radius[i]);
    radius[i] = 0.5 * diameters_[i];
    rmass[i] = 4.0 * kPi / 3.0 * radius[i] * radius[i] * radius[i] * density;
  }
  modify->addstep_compute(update->ntimestep + nevery);
  comm->forward_comm(this);  // ghosts see the new sizes in this step's forces
}

int FixAdaptLiggghts::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  int m = 0;
  for (int k = 0; k < n; ++k) {
    buf[m++] = atom->radius[list[k]];
    buf[m++] = atom->rmass[list[k]];
  }
  return m;
}

void FixAdaptLiggghts::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; ++i) {
    atom->radius[i] = buf[m++];
    atom->rmass[i] = buf[m++];
  }
}

namespace {

FixFactory builtin_adapt = nullptr;

void *create_adapt(void *lmp, int narg, char **arg)
{
  auto *l = static_cast<LAMMPS *>(lmp);
  if (FixAdaptLiggghts::is_liggghts_form(l, narg, arg)) return new FixAdaptLiggghts(l, narg, arg);
  if (!builtin_adapt) l->error->all(FLERR, "fix adapt: this LAMMPS has no built-in fix adapt");
  return builtin_adapt(lmp, narg, arg);
}

}  // namespace

static RegisterStyle reg_adapt("fix", "adapt",
                               "LIGGGHTS fix adapt with an atom-style diameter (other forms go to the built-in)",
                               create_adapt, &builtin_adapt);

}  // namespace dembridge
