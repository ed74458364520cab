#include "fix_particle_distribution.h"

#include <algorithm>
#include <stdexcept>

#include "comm.h"
#include "error.h"
#include "modify.h"
#include "style_registry.h"

#include "fix_particle_template_sphere.h"
#include "insertion_args.h"
#include "restart_record.h"
#include "seed_rule.h"

#include <cstring>
#include <stdexcept>

using namespace LAMMPS_NS;

namespace dembridge {

FixParticleDistribution::FixParticleDistribution(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const std::string prefix = std::string("Fix ") + style + " (id " + id + "): ";
  const bool mass_based = std::strstr(style, "numberbased") == nullptr;
  std::vector<insertion::SphereTemplate> templates;
  std::vector<double> weights;
  try {
    if (narg < 7) throw std::invalid_argument("expects: seed ntemplates template-ID weight ...");
    seed_ = insertion::parse_seed(arg[3]);
    const int ntemplates = insertion::integer_arg(arg[4], "ntemplates");
    if (ntemplates < 1) throw std::invalid_argument("illegal number of templates " + std::string(arg[4]));
    if (narg != 5 + 2 * ntemplates)
      throw std::invalid_argument("# of templates (" + std::to_string(ntemplates) +
                                  ") does not match # of arguments (expected " + std::to_string(ntemplates) +
                                  " pairs of template-ID weight, got " + std::to_string(narg - 5) + " arguments)");
    for (int i = 0; i < ntemplates; ++i) {
      const std::string tid = arg[5 + 2 * i];
      Fix *f = modify->get_fix_by_id(tid);
      if (!f) throw std::invalid_argument("invalid ID for fix particletemplate provided: '" + tid + "'");
      auto *t = FixParticleTemplateSphere::find(lmp, tid);
      if (!t)
        throw std::invalid_argument("fix " + tid + " is not of type particletemplate/sphere (it is " + f->style + ")");
      for (const auto &other : template_ids_)
        if (other == tid) throw std::invalid_argument("cannot use the same template twice ('" + tid + "')");
      const double w = insertion::number_arg(arg[6 + 2 * i], "weight of " + tid);
      if (w < 0) throw std::invalid_argument("invalid weight " + std::string(arg[6 + 2 * i]) + " of " + tid);
      templates.push_back(t->sphere());
      weights.push_back(w);
      template_ids_.push_back(tid);
      template_seeds_.push_back(t->seed());
      template_groupbits_.push_back(t->groupbit);
    }
    double sum = 0.0;
    for (double w : weights) sum += w;
    if (!(sum > 0.0)) throw std::invalid_argument("the weights sum to 0: at least one must be > 0");
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, prefix + e.what());
  }
  restart_global = 1;
  rng_.reset(seed_);  // no rank offset: every rank draws the one-rank stream (rank-invariant insertion)
  dist_ = std::make_unique<insertion::DiscreteDistribution>(templates, weights, mass_based);
  if (dist_->normalised() && comm->me == 0)
    error->warning(FLERR, "particledistribution/discrete: sum of distribution weights != 1, normalizing distribution");
}

namespace {
constexpr double kRecordKind = 2401.;  // particledistribution/discrete, layout 1
}

void FixParticleDistribution::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  insertion::RestartWriter w(kRecordKind);
  w.put(seed_);
  w.put(static_cast<double>(dist_->templates().size()));
  for (std::size_t i = 0; i < dist_->templates().size(); ++i) {
    const auto &t = dist_->templates()[i];
    for (double x : {double(t.type), t.radius, t.density, dist_->number_fractions()[i]}) w.put(x);
  }
  w.put(rng_);
  w.write(fp);
}

// LIGGGHTS 3.8 restores the stream and ignores the seed and templates of the new definition; here a
// changed one stops the run, since the saved stream belongs to the old distribution.
void FixParticleDistribution::restart(char *buf)
{
  const std::string prefix = std::string("Fix ") + style + " (id " + id + ") restart: ";
  const std::string advice = " (define it with the same seed, templates and weights as before write_restart)";
  try {
    insertion::RestartReader r(buf, kRecordKind);
    const int seed = static_cast<int>(r.get());
    if (seed != seed_)
      throw std::invalid_argument("seed " + std::to_string(seed_) + " differs from the seed " + std::to_string(seed) +
                                  " the restart file was written with");
    const std::size_t n = static_cast<std::size_t>(r.get());
    if (n != dist_->templates().size())
      throw std::invalid_argument(std::to_string(dist_->templates().size()) + " templates, the restart file was written with " +
                                  std::to_string(n));
    // the templates first, then the weights (a changed template changes every number fraction)
    std::vector<double> saved(4 * n);
    for (double &x : saved) x = r.get();
    const char *names[4] = {"atom_type", "radius", "density", "weight"};
    for (int k = 0; k < 4; ++k)
      for (std::size_t i = 0; i < n; ++i) {
        const auto &t = dist_->templates()[i];
        const double now[4] = {double(t.type), t.radius, t.density, dist_->number_fractions()[i]};
        if (saved[4 * i + k] != now[k])
          throw std::invalid_argument("template " + template_ids_[i] + ": its " + names[k] +
                                      " differs from the one the restart file was written with");
      }
    r.get(rng_);
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, prefix + e.what() + advice);
  }
}

double FixParticleDistribution::max_radius_of_type(int type) const
{
  double r = 0.0;
  for (const auto &t : dist_->templates())
    if (t.type == type) r = std::max(r, t.radius);
  return r;
}

void FixParticleDistribution::check_seeds_differ(int insert_seed) const
{
  std::vector<int> seeds = {insert_seed, seed_};
  seeds.insert(seeds.end(), template_seeds_.begin(), template_seeds_.end());
  std::sort(seeds.begin(), seeds.end());
  if (std::adjacent_find(seeds.begin(), seeds.end()) != seeds.end())
    throw std::invalid_argument("Random number generation: It is required that all the random seeds of this fix "
                                "insert/*, the random seed of particle distribution fix (id " +
                                std::string(id) + ") and all random seeds of its fix particletemplate/* "
                                "commands are different");
}

FixParticleDistribution *FixParticleDistribution::find(LAMMPS *lmp, const std::string &id)
{
  Fix *f = lmp->modify->get_fix_by_id(id);
  if (!f || std::strncmp(f->style, "particledistribution/discrete", 29) != 0) return nullptr;
  return static_cast<FixParticleDistribution *>(f);
}

static RegisterStyle reg_fix_pdd("fix", "particledistribution/discrete",
                                 "LIGGGHTS discrete particle distribution (mass-based)",
                                 create_fix<FixParticleDistribution>);
static RegisterStyle reg_fix_pdd_mass("fix", "particledistribution/discrete/massbased",
                                      "LIGGGHTS discrete particle distribution (mass-based)",
                                      create_fix<FixParticleDistribution>);
static RegisterStyle reg_fix_pdd_number("fix", "particledistribution/discrete/numberbased",
                                        "LIGGGHTS discrete particle distribution (number-based)",
                                        create_fix<FixParticleDistribution>);

}  // namespace dembridge
