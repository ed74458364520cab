#include "fix_insert_pack.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "modify.h"
#include "region.h"
#include "update.h"
#include "style_registry.h"

#include "fix_particle_distribution.h"
#include "fix_particle_template_sphere.h"
#include "insertion_atoms.h"
#include "lammps_region_view.h"
#include "pack_insertion.h"
#include "restart_record.h"

#include <algorithm>
#include <stdexcept>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace dembridge {

namespace {
constexpr int kRegionSeedOffset = 12;  // LIGGGHTS: the region's stream is reseeded to seed + 12 (+ 2 rank)

insertion::Box box_of(Domain *d)
{
  // the one-rank sub-domain: every rank draws what a one-rank LIGGGHTS run draws
  return {{d->boxlo[0], d->boxlo[1], d->boxlo[2]}, {d->boxhi[0], d->boxhi[1], d->boxhi[2]}};
}
}  // namespace

std::string FixInsertPack::prefix() const { return std::string("Fix ") + style + " (id " + id + "): "; }

FixInsertPack::FixInsertPack(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), rate_(std::string(style) == "insert/rate/region")
{
  std::vector<std::string> args(arg, arg + narg);
  try {
    const int i = insertion::parse_general_keywords(args, k_);
    insertion::parse_pack_keywords(args, i, p_);
    dist_ = FixParticleDistribution::find(lmp, k_.distribution);
    if (!dist_)
      throw std::invalid_argument("Fix insert requires you to define a valid ID for a fix of type "
                                  "particledistribution/discrete: '" + k_.distribution + "' is not one");
    if (p_.region.empty()) throw std::invalid_argument("must define an insertion region ('region ID')");
    region_ = domain->get_region_by_id(p_.region);
    if (!region_) throw std::invalid_argument("region ID '" + p_.region + "' does not exist");
    if (region_->dynamic_check()) throw std::invalid_argument("dynamic regions are not allowed ('" + p_.region + "')");
    if (!region_->bboxflag)
      throw std::invalid_argument("region '" + p_.region + "' has no bounding box: its volume cannot be computed");
    if (k_.insert_every < 0) throw std::invalid_argument("must define 'insert_every' (once or a number of steps)");
    const int ntargets = (p_.volumefraction > 0.) + (p_.ntotal > 0) + (p_.masstotal > 0.);
    if (rate_) {
      if (k_.insert_every == 0) throw std::invalid_argument("'insert_every' = once not allowed");
      if (ntargets) throw std::invalid_argument("unknown keyword or wrong keyword order: "
                                                "volumefraction_region, particles_in_region and mass_in_region "
                                                "belong to insert/pack (use nparticles or mass)");
      if (k_.nparticles <= 0 && k_.mass <= 0. && !k_.n_infinite)
        throw std::invalid_argument("must define either 'nparticles' or 'mass'");
      if (k_.particlerate <= 0. && k_.massrate <= 0.)
        throw std::invalid_argument("must define either 'massrate' or 'particlerate'");
    } else {
      if (k_.nparticles > 0 || k_.mass > 0. || k_.n_infinite)
        throw std::invalid_argument("specifying 'nparticles' or 'mass' not allowed");
      if (k_.particlerate > 0. || k_.massrate > 0.)
        throw std::invalid_argument("specifying 'particlerate' or 'massrate' not allowed");
      if (ntargets != 1)
        throw std::invalid_argument("must define exactly one keyword out of 'volumefraction_region', "
                                    "'particles_in_region', and 'mass_in_region'");
    }
    // after read_restart the saved next step replaces 'start' (init() checks a new fix's start)
    if (k_.start >= 0 && k_.start < update->ntimestep + 1 && modify->nfix_restart_global == 0)
      throw std::invalid_argument("'start' step can not be before current step");
    dist_->check_seeds_differ(k_.seed);
    if (k_.all_in) {
      const double r = dist_->distribution().max_radius();
      LammpsRegionView view(region_);
      for (int d = 0; d < 3; ++d)
        if (view.hi[d] - view.lo[d] < 2. * r)
          throw std::invalid_argument("Impossible to generate random points within region '" + p_.region +
                                      "' - region too small (smaller than twice the particle radius " +
                                      std::to_string(r) + " with all_in yes)");
    }
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, prefix() + e.what());
  }
  insert_rng_.reset(k_.seed);  // LIGGGHTS adds the rank; every rank here draws rank 0's stream
  force_reneighbor = 1;
  next_reneighbor = k_.start >= 0 ? k_.start : update->ntimestep + 1;
  first_next_ = next_reneighbor;
  restart_global = 1;
  vector_flag = 1;
  size_vector = 2;
  global_freq = 1;
  extvector = 0;
}

int FixInsertPack::setmask() { return PRE_EXCHANGE; }

void FixInsertPack::init()
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->all(FLERR, prefix() + "requires atom attributes radius, rmass, omega (atom_style sphere)");
  if (domain->triclinic) error->all(FLERR, prefix() + "Cannot use with triclinic box");
  if (domain->dimension != 3) error->all(FLERR, prefix() + "Can use fix insert for 3d simulations only");
  find_set_property(lmp, k_.set_property, k_.set_property_value, prefix());
  dist_ = FixParticleDistribution::find(lmp, k_.distribution);
  region_ = domain->get_region_by_id(p_.region);
  if (!dist_) error->all(FLERR, prefix() + "particle distribution '" + k_.distribution + "' was deleted");
  if (!region_) error->all(FLERR, prefix() + "regions used by this command must not be deleted ('" + p_.region + "')");
  if (next_reneighbor > 0 && next_reneighbor <= update->ntimestep)  // LIGGGHTS's check of a fix new after a restart
    error->all(FLERR, prefix() + "'start' step can not be before current step (start " + std::to_string(next_reneighbor) +
                          ", current step " + std::to_string(update->ntimestep) + ")");
  for (const auto &t : dist_->distribution().templates())
    if (t.type > atom->ntypes)
      error->all(FLERR, prefix() + "a template inserts atom type " + std::to_string(t.type) +
                            " but there are only " + std::to_string(atom->ntypes) + " atom types");
}

void FixInsertPack::compute_region_volume()
{
  LammpsRegionView view(region_);
  const auto v = insertion::volume_mc(view, box_of(domain), p_.ntry_mc, k_.all_in, dist_->distribution().max_radius(),
                                      region_rng_);
  if (v.inside == 0)
    error->all(FLERR, prefix() + "Unable to calculate the volume of region '" + p_.region +
                          "': it is too small or out of the domain, or the particles are too large for all_in yes");
  region_volume_ = v.global;
  region_volume_local_ = v.local;
}

void FixInsertPack::setup(int)
{
  if (setup_done_) return;
  setup_done_ = true;
  region_->prematch();
  if (!volume_done_) {
    region_rng_.reset(k_.seed + kRegionSeedOffset);
    compute_region_volume();
    volume_done_ = true;
  }
  if (rate_) {  // LIGGGHTS's calc_insertion_properties of insert/rate/region
    const double mass_expect = dist_->distribution().mass_expect();
    ninsert_ = static_cast<long>(k_.nparticles);
    if (ninsert_ == 0 && !k_.n_infinite) ninsert_ = static_cast<long>(k_.mass / mass_expect);
    double nflowrate = k_.particlerate;
    if (nflowrate == 0.) nflowrate = k_.massrate / mass_expect;
    ninsert_per_ = nflowrate * (static_cast<double>(k_.insert_every) * update->dt);
  }
  if (resume_if_more_) {  // as LIGGGHTS: a finished insertion resumes after a restart if the total was raised
    resume_if_more_ = false;
    const bool more = rate_ && (k_.n_infinite || ninserted_ < ninsert_);
    next_reneighbor = more ? std::max(first_next_, update->ntimestep + 1) : 0;  // a past 'start': the next step
    if (more && comm->me == 0)
      utils::logmesg(lmp, "INFO: Particle insertion {}: the total was raised after the restart, resuming at step {}\n",
                     id, next_reneighbor);
  }
  if (comm->me == 0)
    utils::logmesg(lmp, "INFO: Particle insertion {}: inserting every {} steps\n", id, k_.insert_every);
}

int FixInsertPack::count_to_insert()
{
  if (rate_) {  // FixInsert::calc_ninsert_this, then pre_exchange's limit to the total
    int n = static_cast<int>(ninsert_per_ + insert_rng_.uniform());
    if (!k_.n_infinite && ninserted_ + n >= ninsert_) {
      n = static_cast<int>(std::max(0L, ninsert_ - ninserted_));
      k_.exact_number = true;  // LIGGGHTS switches to exact counts for good here
    }
    return n;
  }
  const RegionContent c = region_content(lmp, region_);
  const auto &d = dist_->distribution();
  int n = 0;
  if (p_.volumefraction > 0.) {
    n = static_cast<int>((p_.volumefraction * region_volume_ - c.volume) / d.vol_expect() + insert_rng_.uniform());
    insertion_ratio_ = c.volume / (p_.volumefraction * region_volume_);
  } else if (p_.ntotal > 0) {
    n = p_.ntotal - static_cast<int>(c.count);
    insertion_ratio_ = static_cast<double>(c.count) / static_cast<double>(p_.ntotal);
  } else {
    n = static_cast<int>((p_.masstotal - c.mass) / d.mass_expect() + insert_rng_.uniform());
    insertion_ratio_ = c.mass / p_.masstotal;
  }
  if (n < -200000) error->all(FLERR, prefix() + "overflow in particle number calculation");
  insertion_ratio_ = std::min(1., std::max(0., insertion_ratio_));
  return std::max(n, 0);
}

void FixInsertPack::schedule_next(bool inserted)
{
  const bool more = !rate_ || k_.n_infinite || ninserted_ < ninsert_;
  if (k_.insert_every && more) next_reneighbor += k_.insert_every;
  else if (k_.insert_every) next_reneighbor = 0;
  else next_reneighbor = inserted ? 0 : -1;
}

void FixInsertPack::pre_exchange()
{
  if (next_reneighbor != update->ntimestep || most_recent_ == update->ntimestep) return;
  most_recent_ = update->ntimestep;
  region_->prematch();

  int n = count_to_insert();
  const bool exact = k_.exact_number;
  if (domain->box_change) compute_region_volume();  // LIGGGHTS redraws the volume when the box may change
  if (!exact)
    n = static_cast<int>(region_volume_local_ / region_volume_ * static_cast<double>(n) + insert_rng_.uniform());
  const auto &d = dist_->distribution();
  const std::vector<int> list = d.draw_list(n, exact, dist_->rng());
  if (list.empty()) {
    schedule_next(false);
    return;
  }

  const insertion::Box box = box_of(domain);
  LammpsRegionView view(region_);
  insertion::RegionSampler sampler(view, box);
  if (sampler.empty()) error->all(FLERR, prefix() + "region '" + p_.region + "' lies outside the simulation box");
  std::vector<double> radii;
  for (const auto &t : d.templates()) radii.push_back(t.radius);
  const double rmax = d.max_radius();

  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::max(view.lo[k], box.lo[k]);
    hi[k] = std::min(view.hi[k], box.hi[k]);
  }
  const std::vector<double> near = k_.overlapcheck ? gather_spheres_near(lmp, lo, hi, rmax) : std::vector<double>();
  double rnear = 0.0;
  for (size_t q = 3; q < near.size(); q += 4) rnear = std::max(rnear, near[q]);
  insertion::OverlapGrid grid(lo, hi, rmax + std::max(rmax, rnear));
  for (size_t q = 0; q < near.size(); q += 4) grid.add(&near[q], near[q + 3]);

  const int nlist = static_cast<int>(list.size());
  const int maxtry = rate_ || insertion_ratio_ >= 1.
      ? nlist * k_.maxattempt
      : static_cast<int>(static_cast<double>(nlist * k_.maxattempt) / (1. - insertion_ratio_));
  insertion::PackSettings s;
  s.overlapcheck = k_.overlapcheck;
  s.all_in = k_.all_in;
  s.check_border = p_.check_border;
  s.vel = k_.vel;
  const auto placed = insertion::place(list, radii, sampler, box, s, maxtry, region_rng_, insert_rng_, grid);

  std::vector<NewSphere> spheres;
  double mass = 0.0;
  for (const auto &p : placed) {
    const auto &t = d.templates()[p.template_index];
    NewSphere ns;
    std::copy(p.x, p.x + 3, ns.x);
    std::copy(p.v, p.v + 3, ns.v);
    std::copy(k_.omega, k_.omega + 3, ns.omega);
    ns.radius = t.radius;
    ns.mass = t.mass();
    ns.type = t.type;
    ns.groupbit = groupbit | dist_->groupbit_of(p.template_index);
    spheres.push_back(ns);
    mass += ns.mass;
  }
  create_spheres(lmp, spheres, find_set_property(lmp, k_.set_property, k_.set_property_value, prefix()));
  ninserted_ += static_cast<long>(spheres.size());
  massinserted_ += mass;
  if (comm->me == 0) {
    if (k_.verbose)
      utils::logmesg(lmp,
                     "INFO: Particle insertion {}: inserted {} particle templates (mass {:e}) at step {}\n"
                     " - a total of {} particle templates (mass {:e}) inserted so far.\n",
                     id, spheres.size(), mass, update->ntimestep, ninserted_, massinserted_);
    if (static_cast<int>(spheres.size()) < nlist)
      error->warning(FLERR, "Particle insertion: Less insertions than requested");
  }
  schedule_next(true);
}

void *FixInsertPack::extract(const char *name, int &type)
{
  if (std::string(name) != "radius") return nullptr;
  dist_ = FixParticleDistribution::find(lmp, k_.distribution);  // pair styles ask before this fix's init
  if (!dist_) return nullptr;
  extract_radius_ = dist_->max_radius_of_type(type);
  type = 0;
  return &extract_radius_;
}

namespace {
constexpr double kPackRecord = 2402., kRateRecord = 2403.;  // insert/pack, insert/rate/region, layout 1
}

void FixInsertPack::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  insertion::RestartWriter w(rate_ ? kRateRecord : kPackRecord);
  insertion::put(w, {k_.seed, next_reneighbor, most_recent_, ninserted_, massinserted_, k_.exact_number});
  for (double x : {volume_done_ ? 1. : 0., region_volume_, region_volume_local_}) w.put(x);
  w.put(insert_rng_);
  w.put(region_rng_);
  w.write(fp);
}

// LIGGGHTS 3.8 restores the insert stream, the counts and the next step, and reseeds the region's
// stream (so its restarted run leaves the stream of an uninterrupted one); here both streams and
// the region volume continue where they stopped.
void FixInsertPack::restart(char *buf)
{
  try {
    insertion::RestartReader r(buf, rate_ ? kRateRecord : kPackRecord);
    const insertion::InsertionProgress progress = insertion::get_progress(r, k_.seed);
    const auto next = static_cast<bigint>(progress.next_step);
    most_recent_ = progress.most_recent;
    ninserted_ = progress.ninserted;
    massinserted_ = progress.mass_inserted;
    k_.exact_number = progress.exact_number;
    volume_done_ = r.get_bool();
    region_volume_ = r.get();
    region_volume_local_ = r.get();
    r.get(insert_rng_);
    r.get(region_rng_);
    if (next != 0) next_reneighbor = next;
    else if (k_.insert_every == 0 || !rate_) next_reneighbor = 0;  // insert_every once: done
    else {
      next_reneighbor = 0;  // done unless setup() finds the total raised
      resume_if_more_ = true;
    }
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, prefix() + "restart: " + e.what());
  }
}

double FixInsertPack::compute_vector(int i) { return i == 0 ? static_cast<double>(ninserted_) : massinserted_; }

static RegisterStyle reg_fix_insert_pack("fix", "insert/pack", "LIGGGHTS insertion into a region (fill target)",
                                         create_fix<FixInsertPack>);
static RegisterStyle reg_fix_insert_rate_region("fix", "insert/rate/region",
                                                "LIGGGHTS insertion into a region at a rate", create_fix<FixInsertPack>);

}  // namespace dembridge
