#include "fix_insert_stream.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "modify.h"
#include "update.h"
#include "style_registry.h"

#include "fix_mesh_surface.h"
#include "fix_particle_distribution.h"
#include "insertion_atoms.h"
#include "math/vec3.h"
#include "restart_record.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace dembridge {

namespace {
constexpr int kFaceSeed = 179424799;  // LIGGGHTS: the insertion mesh's own stream, no rank offset
constexpr double kTiny = 1e-14;       // LIGGGHTS's FIX_INSERT_STREAM_TINY (round-off of the step counts)
}  // namespace

using math::dot3;
using math::norm3;

std::string FixInsertStream::prefix() const { return std::string("Fix ") + style + " (id " + id + "): "; }

FixInsertStream::FixInsertStream(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  std::vector<std::string> args(arg, arg + narg);
  try {
    const int i = insertion::parse_general_keywords(args, k_);
    insertion::parse_stream_keywords(args, i, s_);
    dist_ = FixParticleDistribution::find(lmp, k_.distribution);
    if (!dist_)
      throw std::invalid_argument("Fix insert requires you to define a valid ID for a fix of type "
                                  "particledistribution/discrete: '" + k_.distribution + "' is not one");
    if (s_.face.empty()) throw std::invalid_argument("must define an insertion face ('insertion_face ID')");
    if (k_.insert_every < 0 && s_.extrude_length == 0.)
      throw std::invalid_argument("must define either 'insert_every' or 'extrude_length'");
    if (k_.insert_every >= 0 && s_.extrude_length > 0.)
      throw std::invalid_argument("must not provide both 'insert_every' and 'extrude_length'");
    if (s_.extrude_length > 0. && s_.duration > 0)
      throw std::invalid_argument("must not provide both 'extrude_length' and 'duration'");
    if (k_.insert_every == 0) throw std::invalid_argument("'insert_every' must be > 0 (once is not allowed)");
    if (s_.duration > 0 && s_.duration > k_.insert_every)
      throw std::invalid_argument("'duration' > 'insert_every' not allowed");
    if (k_.n_infinite || (k_.nparticles <= 0. && k_.mass <= 0.))
      throw std::invalid_argument("must define either 'nparticles' or 'mass' (LIGGGHTS 3.8's insert/stream "
                                  "does not accept INF)");
    if (k_.particlerate <= 0. && k_.massrate <= 0.)
      throw std::invalid_argument("must define either 'massrate' or 'particlerate'");
    // after read_restart the saved next step replaces 'start' (init() checks a new fix's start)
    if (k_.start >= 0 && k_.start < update->ntimestep + 1 && modify->nfix_restart_global == 0)
      throw std::invalid_argument("'start' step can not be before current step");
    dist_->check_seeds_differ(k_.seed);
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, prefix() + e.what());
  }
  face_fix_ = FixMeshSurface::find(lmp, s_.face, prefix() + "insertion_face");
  face_fix_->keep_whole();  // every rank samples the whole face
  check_face();

  insert_rng_.reset(k_.seed);  // LIGGGHTS adds the rank; every rank here draws rank 0's stream
  face_rng_.reset(kFaceSeed);
  force_reneighbor = 1;
  next_reneighbor = k_.start >= 0 ? k_.start : update->ntimestep + 1;
  first_next_ = next_reneighbor;
  restart_global = 1;
  restart_peratom = 1;
  vector_flag = 1;
  size_vector = 2;
  global_freq = 1;
  extvector = 0;
  create_attribute = 1;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; ++i) set_arrays(i);
}

FixInsertStream::~FixInsertStream()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(release_);
}

// The face: planar, all_in only on mesh/surface/planar, a normal insertion velocity of at least 1e-3.
void FixInsertStream::check_face()
{
  const mesh::TriangleMesh &m = face_fix_->mesh();
  const mesh::Vec3 &n0 = m.normal(0);
  for (int t = 1; t < m.size(); ++t)
    if (std::fabs(mesh::dot(m.normal(t), n0)) <= m.options().curvature)
      error->all(FLERR, prefix() + "command requires a planar face for insertion (fix " + s_.face +
                            ": triangle " + std::to_string(t + 1) + " is not in the plane of triangle 1)");
  if (k_.all_in && std::strcmp(face_fix_->style, "mesh/surface/planar") != 0)
    error->all(FLERR, prefix() + "using all_in yes requires you to use a fix mesh/surface/planar (fix " + s_.face +
                          " is a fix " + face_fix_->style + ")");
  double *n = settings_.normal;
  for (int k = 0; k < 3; ++k) n[k] = n0[k];
  if (dot3(k_.vel.v, n) < 0)
    for (int k = 0; k < 3; ++k) n[k] *= -1.;
  const double vn = dot3(k_.vel.v, n);
  for (int k = 0; k < 3; ++k) v_normal_[k] = n[k] * vn;
  if (norm3(v_normal_) < 1.e-3)
    error->all(FLERR, prefix() + "insertion velocity projected on face normal is < 1e-3 (vel " +
                          std::to_string(k_.vel.v[0]) + " " + std::to_string(k_.vel.v[1]) + " " +
                          std::to_string(k_.vel.v[2]) + ")");
  if (norm3(k_.vel.v) < 1e-5) error->all(FLERR, prefix() + "insertion velocity too low");
  for (int k = 0; k < 3; ++k) p_ref_[k] = m.node(0, 0)[k];
}

int FixInsertStream::setmask() { return PRE_EXCHANGE | END_OF_STEP; }

void FixInsertStream::init()
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, prefix() + "requires atom attributes radius, rmass, omega, torque (atom_style sphere)");
  if (domain->triclinic) error->all(FLERR, prefix() + "Cannot use with triclinic box");
  if (domain->dimension != 3) error->all(FLERR, prefix() + "Can use fix insert for 3d simulations only");
  find_set_property(lmp, k_.set_property, k_.set_property_value, prefix());
  dist_ = FixParticleDistribution::find(lmp, k_.distribution);
  if (!dist_) error->all(FLERR, prefix() + "particle distribution '" + k_.distribution + "' was deleted");
  face_fix_ = FixMeshSurface::find(lmp, s_.face, prefix() + "insertion_face");
  face_fix_->keep_whole();
  if (face_fix_->moving())
    error->all(FLERR, prefix() + "cannot translate, rotate, scale mesh which is used for particle insertion (fix " +
                          s_.face + ")");
  for (const auto &t : dist_->distribution().templates())
    if (t.type > atom->ntypes)
      error->all(FLERR, prefix() + "a template inserts atom type " + std::to_string(t.type) +
                            " but there are only " + std::to_string(atom->ntypes) + " atom types");
  if (next_reneighbor > 0 && next_reneighbor <= update->ntimestep)  // LIGGGHTS's check of a fix new after a restart
    error->all(FLERR, prefix() + "'start' step can not be before current step (start " + std::to_string(next_reneighbor) +
                          ", current step " + std::to_string(update->ntimestep) + ")");
  if (restart_dt_ > 0. && restart_dt_ != update->dt) {
    // the release steps and the insertion period were counted in steps of the old timestep
    int pending = 0, pending_all = 0;
    for (int i = 0; i < atom->nlocal; ++i) pending += release_[i][3] != 0. && release_[i][4] > double(update->ntimestep);
    MPI_Allreduce(&pending, &pending_all, 1, MPI_INT, MPI_SUM, world);
    if (pending_all > 0 || next_reneighbor > 0)
      error->all(FLERR, prefix() + "the timestep (" + std::to_string(update->dt) + ") differs from the one (" +
                            std::to_string(restart_dt_) + ") of the run that wrote the restart file while the insertion "
                            "goes on or particles are in the extrusion volume (keep the timestep until it is done)");
  }
}

// LIGGGHTS's calc_insertion_properties: the period, the extrusion length, the counts.
void FixInsertStream::compute_insertion_properties()
{
  const double dt = update->dt;
  const double vn = norm3(v_normal_);
  const double rmax = dist_->distribution().max_radius();
  const auto &d = dist_->distribution();
  double &L = settings_.extrude_length;
  if (k_.insert_every < 0) {
    L = s_.extrude_length;
    if (L < 3. * rmax)
      error->all(FLERR, prefix() + "'extrude_length' is too small (" + std::to_string(L) +
                            " < 3 x the largest radius " + std::to_string(rmax) + ")");
    insert_every_ = static_cast<int>((L + kTiny) / (dt * vn));
    if (insert_every_ == 0) error->all(FLERR, prefix() + "insertion velocity too high or extrude_length too low");
  } else {
    insert_every_ = k_.insert_every;
    const int duration = s_.duration > 0 ? s_.duration : insert_every_;
    L = static_cast<double>(duration) * dt * vn;
    if (L < 3. * rmax)
      error->all(FLERR, prefix() + "'insert_every' or 'vel' is too small, or radius of inserted particles too large "
                                   "(extrusion length " + std::to_string(L) + " < 3 x the largest radius " +
                            std::to_string(rmax) + ")");
  }
  settings_.extrude_min = 0.;
  settings_.extrude_max = L;
  ninsert_ = k_.nparticles > 0. ? static_cast<long>(static_cast<int>(k_.nparticles))
                                : static_cast<long>(static_cast<int>((k_.mass + kTiny) / d.mass_expect()));
  double nflowrate = k_.particlerate;
  if (nflowrate == 0.) nflowrate = k_.massrate / d.mass_expect();
  ninsert_per_ = nflowrate * (static_cast<double>(insert_every_) * dt);

  const mesh::TriangleMesh &m = face_fix_->mesh();
  std::vector<insertion::Triangle> tris(m.size());
  std::vector<double> areas(m.size());
  std::vector<unsigned> border(m.size(), 0u);
  for (int t = 0; t < m.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) tris[t][k][c] = m.node(t, k)[c];
      if (m.edge_active(t, k)) border[t] |= 1u << k;
    }
    // LIGGGHTS's TriMesh::calcArea (unit edge vectors times lengths)
    areas[t] = 0.5 * mesh::norm(mesh::cross(m.edge_vec(t, 0), m.edge_vec(t, 1))) * m.edge_len(t, 0) * m.edge_len(t, 1);
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) {
        const double x = m.node(t, k)[c], xe = x - settings_.normal[c] * L;
        const bool first = t == 0 && k == 0;
        vol_lo_[c] = first ? std::min(x, xe) : std::min({vol_lo_[c], x, xe});
        vol_hi_[c] = first ? std::max(x, xe) : std::max({vol_hi_[c], x, xe});
      }
  }
  face_ = std::make_unique<insertion::StreamFace>(tris, areas, border);
  settings_.overlapcheck = k_.overlapcheck;
  settings_.all_in = k_.all_in;
}

void FixInsertStream::setup(int)
{
  if (setup_done_) return;
  setup_done_ = true;
  compute_insertion_properties();
  if (resume_if_more_) {  // as LIGGGHTS: a finished insertion resumes after a restart if the total was raised
    resume_if_more_ = false;
    next_reneighbor = ninserted_ < ninsert_ ? std::max(first_next_, update->ntimestep + 1) : 0;  // a past 'start': the next step
    if (next_reneighbor && comm->me == 0)
      utils::logmesg(lmp, "INFO: Particle insertion {}: the total was raised after the restart, resuming at step {}\n",
                     id, next_reneighbor);
  }
  if (comm->me == 0)
    utils::logmesg(lmp, "INFO: Particle insertion {}: {:f} particles every {} steps - particle rate {:f}\n"
                        "      {} particles, extrusion length {:g}\n",
                   id, ninsert_per_, insert_every_, ninsert_per_ / (insert_every_ * update->dt), ninsert_, settings_.extrude_length);
}

int FixInsertStream::count_to_insert()
{
  // FixInsert::calc_ninsert_this and pre_exchange's limit to the total
  int n = static_cast<int>(ninsert_per_ + insert_rng_.uniform());
  if (ninserted_ + n > ninsert_) n = static_cast<int>(ninsert_ - ninserted_);
  if (ninserted_ + n >= ninsert_) {
    n = static_cast<int>(std::max(0L, ninsert_ - ninserted_));
    k_.exact_number = true;  // LIGGGHTS switches to exact counts for good here
  }
  // distribute_ninsert_this on one rank: the share of the extrusion volume in the box, drawn at the
  // first insertion and again whenever the box may change
  const Domain *d = domain;
  for (int k = 0; k < 3; ++k) {
    settings_.box.lo[k] = d->boxlo[k];
    settings_.box.hi[k] = d->boxhi[k];
  }
  if (!fraction_done_ || domain->box_change) {
    fraction_ = insertion::fraction_in_box(*face_, settings_, s_.ntry_mc, face_rng_, insert_rng_);
    fraction_done_ = true;
    // LIGGGHTS 3.8 checks the shares summed over the ranks: on one rank, the share in the box
    if (fraction_ < 0.9 || fraction_ > 1.1)
      error->all(FLERR, prefix() + "insertion volume could not be distributed properly in parallel. Bad decomposition "
                                   "or insertion face extrusion is too small or outside domain (" +
                            std::to_string(fraction_) + " of the extrusion volume is inside the box, needs 0.9 to 1.1)");
  }
  if (s_.parallel) insertion::narrow_to_box(settings_, p_ref_);  // geometry of the box only: the same at every call
  if (!k_.exact_number) return static_cast<int>(fraction_ * static_cast<double>(n) + insert_rng_.uniform());
  return n;
}

void FixInsertStream::pre_exchange()
{
  if (next_reneighbor != update->ntimestep || most_recent_ == update->ntimestep) return;
  most_recent_ = update->ntimestep;
  if (comm->me == 0) {
    bool inside = true;
    for (int k = 0; k < 3; ++k)
      inside = inside && vol_lo_[k] >= domain->boxlo[k] && vol_lo_[k] <= domain->boxhi[k] &&
          vol_hi_[k] >= domain->boxlo[k] && vol_hi_[k] <= domain->boxhi[k];  // LIGGGHTS's is_in_domain
    if (!inside)
      error->warning(FLERR, "Fix insert/stream: Extruded insertion face extends outside domain, may not insert all "
                            "particles correctly");
  }
  const int n = count_to_insert();
  const auto &d = dist_->distribution();
  const std::vector<int> list = d.draw_list(n, k_.exact_number, dist_->rng());
  const bool more = ninserted_ < ninsert_;
  if (list.empty()) {
    if (comm->me == 0) error->warning(FLERR, "Particle insertion: Inserting no particle - check particle insertion settings");
    if (more) next_reneighbor += insert_every_;
    else next_reneighbor = 0;  // done (LIGGGHTS leaves the past step, which never comes again)
    return;
  }

  std::vector<double> radii;
  for (const auto &t : d.templates()) radii.push_back(t.radius);
  const double rmax = d.max_radius();
  const std::vector<double> near =
      k_.overlapcheck ? gather_spheres_near(lmp, vol_lo_, vol_hi_, 2. * rmax) : std::vector<double>();
  double rnear = 0.0;
  for (size_t q = 3; q < near.size(); q += 4) rnear = std::max(rnear, near[q]);
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = vol_lo_[k] - rmax;
    hi[k] = vol_hi_[k] + rmax;
  }
  insertion::OverlapGrid grid(lo, hi, rmax + std::max(rmax, rnear));
  for (size_t q = 0; q < near.size(); q += 4) grid.add(&near[q], near[q + 3]);

  bool bad_within = false;
  const int nlist = static_cast<int>(list.size());
  const auto placed = insertion::place_stream(list, radii, *face_, settings_, nlist * k_.maxattempt, face_rng_,
                                              insert_rng_, grid, bad_within);
  if (bad_within && comm->me == 0) error->warning(FLERR, "'All_in yes' did not succeed");

  std::vector<NewSphere> spheres;
  double mass = 0.0;
  for (const auto &p : placed) {
    const auto &t = d.templates()[p.template_index];
    NewSphere ns;
    std::copy(p.x, p.x + 3, ns.x);
    std::copy(v_normal_, v_normal_ + 3, ns.v);  // the normal velocity only, no spin, until the face
    std::fill(ns.omega, ns.omega + 3, 0.0);
    ns.radius = t.radius;
    ns.mass = t.mass();
    ns.type = t.type;
    ns.groupbit = groupbit | dist_->groupbit_of(p.template_index);
    spheres.push_back(ns);
    mass += ns.mass;
  }
  // LIGGGHTS 3.8 draws the release velocities (vel uniform/gaussian) right after the insertion, one
  // particle after the other in insertion (= id) order
  std::vector<std::array<double, 3>> v_release(spheres.size());
  for (auto &vr : v_release) k_.vel.draw(insert_rng_, vr.data());
  const int nlocal_before = atom->nlocal;
  create_spheres(lmp, spheres, find_set_property(lmp, k_.set_property, k_.set_property_value, prefix()));
  // LIGGGHTS's finalize_insertion: release when the centre reaches the face
  const int step = static_cast<int>(update->ntimestep);
  const double vn_dt = norm3(v_normal_) * update->dt;
  size_t next = 0;
  for (int i = nlocal_before; i < atom->nlocal; ++i) {
    double rel[3];
    for (int k = 0; k < 3; ++k) rel[k] = p_ref_[k] - atom->x[i][k];
    const int n_steps = static_cast<int>((dot3(rel, settings_.normal) + kTiny) / vn_dt);
    for (int k = 0; k < 3; ++k) release_[i][k] = atom->x[i][k];
    release_[i][3] = static_cast<double>(step);
    release_[i][4] = static_cast<double>(step + n_steps);
    for (int k = 0; k < 3; ++k) release_[i][5 + k] = v_normal_[k];
    // this rank's new atoms are those of `spheres` in its sub-domain, in list order
    while (!std::equal(atom->x[i], atom->x[i] + 3, spheres[next].x)) ++next;
    for (int k = 0; k < 3; ++k) release_[i][8 + k] = v_release[next][k];
    ++next;
  }
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
  if (ninserted_ < ninsert_) next_reneighbor += insert_every_;
  else next_reneighbor = 0;
}

// LIGGGHTS's end_of_step: a particle in the extrusion volume moves at v_n with no force, torque or
// spin; on its release step it gets its release velocity and omega.
void FixInsertStream::end_of_step()
{
  const int step = static_cast<int>(update->ntimestep);
  const double dt = update->dt;
  double **x = atom->x, **v = atom->v, **f = atom->f, **omega = atom->omega, **torque = atom->torque;
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit) || release_[i][3] == 0.) continue;
    const int i_step = static_cast<int>(release_[i][3] + kTiny);
    const int r_step = static_cast<int>(release_[i][4] + kTiny);
    if (step > r_step) continue;
    const double elapsed = static_cast<double>(step - i_step) * dt;
    for (int k = 0; k < 3; ++k) {
      x[i][k] = release_[i][k] + release_[i][5 + k] * elapsed;
      v[i][k] = release_[i][5 + k];
      omega[i][k] = f[i][k] = torque[i][k] = 0.0;
    }
    if (step == r_step)
      for (int k = 0; k < 3; ++k) {
        v[i][k] = release_[i][8 + k];
        omega[i][k] = k_.omega[k];
      }
  }
}

void *FixInsertStream::extract(const char *name, int &type)
{
  if (std::string(name) != "radius") return nullptr;
  dist_ = FixParticleDistribution::find(lmp, k_.distribution);  // pair styles ask before this fix's init
  if (!dist_) return nullptr;
  extract_radius_ = dist_->max_radius_of_type(type);
  type = 0;
  return &extract_radius_;
}

namespace {
constexpr double kStreamRecord = 2404.;  // insert/stream, layout 1
}

void FixInsertStream::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  insertion::RestartWriter w(kStreamRecord);
  insertion::put(w, {k_.seed, next_reneighbor, most_recent_, ninserted_, massinserted_, k_.exact_number});
  for (double x : {fraction_done_ ? 1. : 0., fraction_, update->dt}) w.put(x);
  w.put(insert_rng_);
  w.put(face_rng_);
  w.write(fp);
}

// LIGGGHTS 3.8 restores the insert stream, the counts, the next step and the release data, but
// restarts the face's stream from its seed and redraws the share of the extrusion volume in the
// box (so its restarted run leaves the streams of an uninterrupted one); here everything continues.
void FixInsertStream::restart(char *buf)
{
  try {
    insertion::RestartReader r(buf, kStreamRecord);
    const insertion::InsertionProgress progress = insertion::get_progress(r, k_.seed);
    const auto next = static_cast<bigint>(progress.next_step);
    most_recent_ = progress.most_recent;
    ninserted_ = progress.ninserted;
    massinserted_ = progress.mass_inserted;
    k_.exact_number = progress.exact_number;
    fraction_done_ = r.get_bool();
    fraction_ = r.get();
    restart_dt_ = r.get();
    r.get(insert_rng_);
    r.get(face_rng_);
    if (next != 0) next_reneighbor = next;
    else {
      next_reneighbor = 0;  // done unless setup() finds the total raised
      resume_if_more_ = true;
    }
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, prefix() + "restart: " + e.what());
  }
}

// Per-atom restart layout: [kRelease + 1, release state] (LAMMPS skips a fix's block by its size).
int FixInsertStream::pack_restart(int i, double *buf)
{
  buf[0] = kRelease + 1;
  std::copy(release_[i], release_[i] + kRelease, buf + 1);
  return kRelease + 1;
}

void FixInsertStream::unpack_restart(int nlocal, int nth)
{
  const double *extra = atom->extra[nlocal];
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[m]);
  if (static_cast<int>(extra[m]) != kRelease + 1)
    error->one(FLERR, prefix() + "restart: the per-atom data of atom " + std::to_string(atom->tag[nlocal]) +
                          " are not those of a fix insert/stream (written by another plugin version?)");
  std::copy(extra + m + 1, extra + m + 1 + kRelease, release_[nlocal]);
}

double FixInsertStream::compute_vector(int i) { return i == 0 ? static_cast<double>(ninserted_) : massinserted_; }

void FixInsertStream::grow_arrays(int nmax) { memory->grow(release_, nmax, kRelease, "insert/stream:release"); }

void FixInsertStream::copy_arrays(int i, int j, int)
{
  std::copy(release_[i], release_[i] + kRelease, release_[j]);
}

void FixInsertStream::set_arrays(int i) { std::fill(release_[i], release_[i] + kRelease, 0.0); }

int FixInsertStream::pack_exchange(int i, double *buf)
{
  std::copy(release_[i], release_[i] + kRelease, buf);
  return kRelease;
}

int FixInsertStream::unpack_exchange(int nlocal, double *buf)
{
  std::copy(buf, buf + kRelease, release_[nlocal]);
  return kRelease;
}

double FixInsertStream::memory_usage() { return static_cast<double>(atom->nmax) * kRelease * sizeof(double); }

static RegisterStyle reg_fix_insert_stream("fix", "insert/stream",
                                           "LIGGGHTS insertion through a mesh face at a rate", create_fix<FixInsertStream>);

}  // namespace dembridge
