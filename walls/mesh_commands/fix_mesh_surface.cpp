// fix mesh/surface, fix mesh/surface/stress (spec liggghts-walls §4, §6, §7.3, §8).
#include "fix_mesh_surface.h"

#include "finnie_wear.h"
#include "rank_error.h"
#include "fix_move_mesh.h"
#include "fix_property_global.h"
#include "mesh_args.h"
#include "stl_reader.h"
#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;

namespace dembridge {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

FixMeshSurface::FixMeshSurface(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const std::string cmd = std::string("fix ") + style + " (id " + id + ")";
  MeshArgs a(lmp, cmd, narg, arg, 3);
  stress_ = std::strcmp(style, "mesh/surface/stress") == 0;
  const bool stress_style = stress_;
  register_dump_styles(lmp);  // dump mesh/stl, mesh/vtk in this LAMMPS instance (style_registry.h)

  // fixed order as in LIGGGHTS: file F type T, then optional keywords in any order
  a.expect_keyword("file", "file FILENAME type T");
  file_ = a.word("file name");
  const std::string &file = file_;
  a.expect_keyword("type", "type T after the file name");
  wall_type_ = a.integer("type");
  if (wall_type_ < 1 || wall_type_ > atom->ntypes)
    error->all(FLERR, cmd + ": type " + std::to_string(wall_type_) + " is outside 1.." + std::to_string(atom->ntypes) +
                          " (the atom types of create_box; the wall material needs a type)");

  mesh::MeshOptions &opt = opt_;
  std::vector<mesh::PlacementOp> &ops = ops_;
  mesh::Vec3 ref{0.0, 0.0, 0.0};
  bool have_surface_vel = false, have_surface_ang = false;
  mesh::Vec3 surface_vel{}, ang_origin{}, ang_axis{};
  double ang_omega = 0.0;
  while (!a.done()) {
    const std::string key = a.word("keyword");
    if (key == "precision") {
      opt.precision = a.positive("precision");
    } else if (key == "heal") {
      const std::string v = a.word("heal");
      if (v != "auto_remove_duplicates" && v != "no")
        a.fail("heal", "expected 'auto_remove_duplicates' or 'no', got '" + v + "'");
      opt.heal_remove_duplicates = v == "auto_remove_duplicates";
    } else if (key == "distribute") {
      distribute_ = a.yes_no("distribute");
    } else if (key == "verbose") {
      a.yes_no("verbose");
    } else if (key == "scale") {
      ops.push_back({mesh::PlacementOp::Scale, {}, a.positive("scale")});
    } else if (key == "move") {
      ops.push_back({mesh::PlacementOp::Move, a.vec3("move"), 0.0});
    } else if (key == "rotate") {
      a.expect_keyword("axis", "rotate axis ax ay az angle deg");
      const mesh::Vec3 axis = a.nonzero_vec3("rotate axis");
      a.expect_keyword("angle", "rotate axis ax ay az angle deg");
      ops.push_back({mesh::PlacementOp::Rotate, axis, a.number("rotate angle")});
    } else if (key == "curvature") {
      const double deg = a.number("curvature");
      if (!(deg > 0.0 && deg < 60.0)) a.fail("curvature", "expected an angle with 0 < curvature < 60 degrees");
      opt.curvature = std::cos(deg * kPi / 180.0);
    } else if (key == "curvature_tolerant") {
      opt.curvature_tolerant = a.yes_no("curvature_tolerant");
    } else if (key == "surface_vel") {
      surface_vel = a.vec3("surface_vel");
      have_surface_vel = true;
    } else if (key == "surface_ang_vel") {
      a.expect_keyword("origin", "surface_ang_vel origin ox oy oz axis ax ay az omega w");
      ang_origin = a.vec3("surface_ang_vel origin");
      a.expect_keyword("axis", "surface_ang_vel origin ox oy oz axis ax ay az omega w");
      ang_axis = a.nonzero_vec3("surface_ang_vel axis");
      a.expect_keyword("omega", "surface_ang_vel origin ox oy oz axis ax ay az omega w");
      ang_omega = a.number("surface_ang_vel omega");
      have_surface_ang = true;
    } else if (stress_style && key == "reference_point") {
      ref = a.vec3("reference_point");
    } else if (stress_style && key == "stress") {
      stress_ = a.on_off("stress");
    } else if (stress_style && key == "wear") {
      const std::string v = a.word("wear");
      if (v != "off" && v != "finnie") a.fail("wear", "expected 'finnie' or 'off', got '" + v + "'");
      wear_ = v == "finnie";
    } else if (key == "reference_point" || key == "stress" || key == "wear") {
      a.fail(key, "is a keyword of fix mesh/surface/stress, not of fix " + std::string(style));
    } else {
      a.fail(key, "unknown keyword (expected precision, heal, distribute, verbose, scale, move, rotate, curvature, "
                  "curvature_tolerant, surface_vel, surface_ang_vel" +
                      std::string(stress_style ? ", reference_point, stress, wear" : "") + ")");
    }
  }
  if (have_surface_vel && have_surface_ang) a.fail("surface_ang_vel", "cannot be combined with surface_vel");

  try {
    mesh_ = read_mesh();
  } catch (const mesh::MeshError &e) {
    error->all(FLERR, cmd + " file '" + file + "': " + e.what());
  }
  digest_ = mesh_->node_digest();
  ref_point_ = mesh_->attach_point(ref);
  conveyor_ = have_surface_vel || have_surface_ang;
  conveyor_args_ = {have_surface_vel, surface_vel, ang_origin, ang_axis, ang_omega};
  if (conveyor_) set_surface_velocity();
  tri_force_.assign(3 * std::size_t(mesh_->size()), 0.0);
  if (wear_ && !stress_) a.fail("wear finnie", "needs 'stress on' (the wear is computed with the wall forces)");
  if (wear_) {
    wear_total_.assign(std::size_t(mesh_->size()), 0.0);
    wear_step_.assign(std::size_t(mesh_->size()), 0.0);
  }

  restart_global = 1;
  force_reneighbor = 1;
  next_reneighbor = -1;
  if (std::strcmp(style, "mesh/surface/stress") == 0) {
    vector_flag = 1;
    size_vector = 9;
    global_freq = 1;
    extvector = 1;
  }
  if (comm->me == 0)
    utils::logmesg(lmp, "{}: {} triangles from '{}'{}, {:.1f} kB per rank\n", cmd, mesh_->size(), file,
                   mesh_->removed_duplicates() ? " (" + std::to_string(mesh_->removed_duplicates()) + " duplicates removed)" : "",
                   mesh_->memory_bytes() / 1024.0);
}

FixMeshSurface::~FixMeshSurface() = default;

int FixMeshSurface::setmask()
{
  int mask = PRE_EXCHANGE | PRE_NEIGHBOR | POST_NEIGHBOR | PRE_FORCE | POST_RUN;
  if (vector_flag) mask |= FINAL_INTEGRATE;
  return mask;
}

// surface_vel / surface_ang_vel: a conveyor; node velocity = the in-plane part of the given
// velocity, rescaled to the full magnitude (spec §7.1).
void FixMeshSurface::set_surface_velocity()
{
  const auto &[linear, v, origin, axis, omega] = conveyor_args_;
  mesh::TriangleMesh &m = *mesh_;
  m.zero_velocity();
  const mesh::Vec3 w = mesh::scale(mesh::div_by(axis, mesh::norm(axis)), omega);
  for (int t = 0; t < m.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const mesh::Vec3 full = linear ? v : mesh::cross(w, mesh::sub(m.node(t, k), origin));
      const mesh::Vec3 &n = m.normal(t);
      const mesh::Vec3 inplane = mesh::sub(full, mesh::scale(n, mesh::dot(full, n)));
      const double li = mesh::norm(inplane);
      if (li > 0.0) m.add_node_velocity(t, k, mesh::scale(inplane, mesh::norm(full) / li));
    }
}

void FixMeshSurface::init()
{
  if (!atom->radius_flag) error->all(FLERR, std::string("fix ") + style + " (id " + id + ") requires atom attribute radius (atom_style sphere)");
  movers_.clear();
  for (Fix *f : modify->get_fix_list())
    if (auto *mv = dynamic_cast<FixMoveMesh *>(f); mv && mv->mesh_id() == id) movers_.push_back(mv);
  if (conveyor_ && !movers_.empty())
    error->all(FLERR, std::string("fix ") + style + " (id " + id + "): surface_vel/surface_ang_vel cannot be combined with fix move/mesh");
  // an empty box is wrapped around the meshes already for the other fixes' init and setup
  if (atom->natoms == 0 && domain->nonperiodic == 2 && leads_box_wrap())
    ShrinkWrapAroundMeshes::set_empty_box(domain, all_meshes_extent());
  if (wear_) {
    const std::string caller = std::string("fix ") + style + " (id " + id + ") wear finnie";
    const property::GlobalProperty *k = FixPropertyGlobal::find(lmp, "k_finnie");
    if (!k) error->all(FLERR, property::missing_property_message("k_finnie", caller));
    try {
      k->require(property::Kind::PerTypePair, atom->ntypes, caller);
    } catch (const std::exception &e) {
      error->all(FLERR, e.what());
    }
    k_finnie_.assign(std::size_t(atom->ntypes + 1), 0.0);
    for (int t = 1; t <= atom->ntypes; ++t) k_finnie_[t] = k->per_type_pair(wall_type_, t);
  }
}

// LIGGGHTS: k_finnie[wall type][particle type]; the particle must be in the mesh fix's group.
void FixMeshSurface::add_wear(int tri, const double *x, const double *v, const double *cp, const double *v_wall,
                              const double *f, int atom_type)
{
  if (!wear_ || update->setupflag) return;  // LIGGGHTS counts no wear for the setup forces
  const mesh::Vec3 c{cp[0] - x[0], cp[1] - x[1], cp[2] - x[2]};
  const mesh::Vec3 v_rel{v[0] - v_wall[0], v[1] - v_wall[1], v[2] - v_wall[2]};
  const double fmag = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  wear_step_[std::size_t(tri)] += mesh::finnie_wear_increment(c, v_rel, mesh_->normal(tri), k_finnie_[std::size_t(atom_type)], fmag,
                                                              update->dt, mesh_->area(tri));
}

int FixMeshSurface::mover_rank(const FixMoveMesh *mover) const
{
  for (std::size_t i = 0; i < movers_.size(); ++i)
    if (movers_[i] == mover) return int(i);
  return -1;
}

// LIGGGHTS stops when every element is outside a non-periodic box; partly outside only warns.
void FixMeshSurface::check_domain()
{
  const std::string who = std::string("fix ") + style + " (id " + id + ")";
  if (mesh_->whole()) {  // a distributed mesh repeats the warnings of its last whole check
    outside_ = 0;
    crosses_periodic_ = false;
  for (int t = 0; t < mesh_->size(); ++t) {
    bool out = false;
    for (int d = 0; d < 3; ++d) {
      double lo = mesh_->node(t, 0)[d], hi = lo;
      for (int k = 1; k < 3; ++k) {
        lo = std::min(lo, mesh_->node(t, k)[d]);
        hi = std::max(hi, mesh_->node(t, k)[d]);
      }
      if (domain->periodicity[d]) {
        if (lo < domain->boxlo[d] || hi > domain->boxhi[d]) crosses_periodic_ = true;
      } else if (hi < domain->boxlo[d] || lo > domain->boxhi[d]) {
        out = true;
      }
    }
    outside_ += out;
  }
  }
  const int outside = outside_;
  const bool crosses_periodic = crosses_periodic_;
  if (outside == mesh_->global_size())
    error->all(FLERR, who + ": all " + std::to_string(outside) + " mesh elements are outside the simulation box");
  if (comm->me == 0 && outside > 0)
    error->warning(FLERR, who + ": " + std::to_string(outside) + " mesh elements are outside the simulation box");
  if (comm->me == 0 && crosses_periodic)
    error->warning(FLERR, who + ": the mesh crosses a periodic boundary; meshes are not wrapped, so particles "
                              "interact only with the mesh as placed");
}

void FixMeshSurface::remember_nodes()
{
  if (!moving()) {  // only a moving mesh checks its displacement since the last build
    std::vector<mesh::TriangleNodes>().swap(nodes_at_build_);
    return;
  }
  nodes_at_build_.resize(mesh_->size());
  for (int t = 0; t < mesh_->size(); ++t) nodes_at_build_[t] = mesh_->nodes(t);
}

// LIGGGHTS's reset_box takes the mesh nodes into a shrink-wrapped box's extent, at the setup and at
// every re-neighbouring (a moving mesh carries the box along): the faces are opened before the
// reset_box of the re-neighbouring (pre_exchange) and closed after it (pre_neighbor).
void FixMeshSurface::setup_pre_exchange() { open_box_wrap(); }
void FixMeshSurface::pre_exchange() { open_box_wrap(); }
void FixMeshSurface::post_run() { close_box_wrap(); }

void FixMeshSurface::open_box_wrap()
{
  if (domain->nonperiodic == 2 && leads_box_wrap()) box_wrap_.open(domain, all_meshes_extent(), atom->natoms);
}

// The first mesh fix in fix order wraps the box around all of them.
bool FixMeshSurface::leads_box_wrap() const
{
  for (Fix *f : modify->get_fix_list())
    if (dynamic_cast<FixMeshSurface *>(f)) return f == this;
  return false;
}

MeshExtent FixMeshSurface::all_meshes_extent() const
{
  MeshExtent all;
  for (Fix *f : modify->get_fix_list())
    if (auto *m = dynamic_cast<FixMeshSurface *>(f)) {
      const MeshExtent e = m->extent();
      if (!e.empty) all.add(e.lo, e.hi);
    }
  return all;
}

// A part of a mesh is kept only while it never moved: its extent is the whole mesh's at the split.
MeshExtent FixMeshSurface::extent() const { return mesh_->whole() ? node_extent(*mesh_) : split_extent_; }

void FixMeshSurface::setup_pre_neighbor()
{
  close_box_wrap();
  check_domain();  // in the box of the run, wrapped around the meshes (LIGGGHTS checks at its setup too)
  remember_nodes();
}

// §7.3: a moving mesh recomputes its vectors from the nodes at every re-neighbouring step.
void FixMeshSurface::pre_neighbor()
{
  close_box_wrap();
  if (moving()) mesh_->refresh_geometry();
  remember_nodes();
  rebuilt_this_step_ = true;
}

void FixMeshSurface::setup_post_neighbor()
{
  build_candidates();
  log_distribution();
}
void FixMeshSurface::post_neighbor() { build_candidates(); }

void FixMeshSurface::build_candidates()
{
  const double s = moving() ? neighbor->skin : 0.5 * neighbor->skin;
  if (distribute_ && !keep_whole_ && !moving() && !wear_ && !mesh_->moved() && !domain->triclinic) fit_to_reach(s);
  else keep_whole();
  neighbors_.build(*mesh_, atom->nlocal, atom->x, atom->radius, nullptr, s);
}

std::unique_ptr<mesh::TriangleMesh> FixMeshSurface::read_mesh() const
{
  std::vector<mesh::TriangleNodes> tris = mesh::read_stl(file_);
  mesh::apply_placement(tris, ops_);
  return std::make_unique<mesh::TriangleMesh>(std::move(tris), opt_);
}

void FixMeshSurface::keep_whole()
{
  keep_whole_ = true;
  if (!mesh_->whole()) reload_whole();
  split_ = false;
}

// A distributed mesh never moved, so the file gives its nodes again bit for bit.
void FixMeshSurface::reload_whole()
{
  const std::string who = std::string("fix ") + style + " (id " + id + ")";
  std::unique_ptr<mesh::TriangleMesh> fresh;
  try {
    fresh = read_mesh();
  } catch (const mesh::MeshError &e) {
    fail_on_this_rank(lmp, FLERR, who + ": reading '" + file_ + "' again for the triangles this rank needs now: " + e.what());
  }
  if (fresh->node_digest() != digest_)
    fail_on_this_rank(lmp, FLERR, who + ": '" + file_ + "' changed since the mesh was defined (read again for the "
                                        "triangles this rank needs now); restore it or use 'distribute no'");
  fresh->take_attached_points(*mesh_);
  const bool had_velocity = mesh_->has_velocity();
  *mesh_ = std::move(*fresh);
  if (conveyor_) set_surface_velocity();
  else if (had_velocity) mesh_->zero_velocity();
  std::vector<double>(3 * std::size_t(mesh_->size()), 0.0).swap(tri_force_);
}

// Keep the triangles whose bounding box meets this rank's region: its subdomain and its atoms'
// reach (radius + s, the candidate criterion's superset), grown by the neighbour cutoff so that
// atoms may move and the box may change a little before the region has to be refitted. A candidate
// of an atom lies within its reach, so every rank finds the candidates of the replicated mesh.
void FixMeshSurface::fit_to_reach(double s)
{
  mesh::Vec3 mlo, mhi;
  mesh_->bounding_box(mlo, mhi);
  // a part that spans the whole mesh's box (one rank) holds every triangle any atom can need
  bool spans = split_;
  for (int d = 0; d < 3; ++d) spans = spans && kept_lo_[d] <= mlo[d] && kept_hi_[d] >= mhi[d];
  if (spans) return;
  mesh::Vec3 lo{domain->sublo[0], domain->sublo[1], domain->sublo[2]};
  mesh::Vec3 hi{domain->subhi[0], domain->subhi[1], domain->subhi[2]};
  mesh::Vec3 need_lo = mhi, need_hi = mlo;  // empty
  for (int i = 0; i < atom->nlocal; ++i)
    for (int d = 0; d < 3; ++d) {
      const double x = atom->x[i][d], r = atom->radius[i] + s;
      const double eps = 1e-9 * (std::fabs(x) + r);  // rounding of the criterion's bounds
      need_lo[d] = std::min(need_lo[d], x - r - eps);
      need_hi[d] = std::max(need_hi[d], x + r + eps);
    }
  bool inside = true;
  for (int d = 0; d < 3; ++d) {
    need_lo[d] = std::max(need_lo[d], mlo[d]);
    need_hi[d] = std::min(need_hi[d], mhi[d]);
    if (need_lo[d] <= need_hi[d] && (need_lo[d] < kept_lo_[d] || need_hi[d] > kept_hi_[d])) inside = false;
  }
  if (split_ && inside) return;
  const double grow = neighbor->cutneighmax + s;
  for (int d = 0; d < 3; ++d) {
    kept_lo_[d] = std::max(std::min(lo[d], need_lo[d]) - grow, mlo[d]);
    kept_hi_[d] = std::min(std::max(hi[d], need_hi[d]) + grow, mhi[d]);
  }
  if (!mesh_->whole()) reload_whole();
  split_extent_ = node_extent(*mesh_);
  std::vector<int> ids;
  for (int t = 0; t < mesh_->size(); ++t) {
    bool meets = true;
    for (int d = 0; d < 3 && meets; ++d) {
      const double a = mesh_->node(t, 0)[d], b = mesh_->node(t, 1)[d], c = mesh_->node(t, 2)[d];
      meets = std::max(a, std::max(b, c)) >= kept_lo_[d] && std::min(a, std::min(b, c)) <= kept_hi_[d];
    }
    if (meets) ids.push_back(t);
  }
  mesh_->keep_only(ids);
  std::vector<double>(3 * std::size_t(mesh_->size()), 0.0).swap(tri_force_);
  split_ = true;
}

// Collective: how the triangles are spread over the ranks (after the setup's first fit).
void FixMeshSurface::log_distribution()
{
  const double mine[2] = {double(mesh_->size()), memory_usage()};
  double lo[2], hi[2];
  const double neg[2] = {-mine[0], -mine[1]};
  MPI_Allreduce(mine, hi, 2, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(neg, lo, 2, MPI_DOUBLE, MPI_MAX, world);
  if (comm->me == 0)
    utils::logmesg(lmp, "fix {} (id {}): {} of {} triangles per rank ({} to {}), mesh memory {:.1f} to {:.1f} kB per rank\n",
                   style, id, mesh_->whole() ? "all" : "part", mesh_->global_size(), -lo[0], hi[0], -lo[1] / 1024.0,
                   hi[1] / 1024.0);
}

void FixMeshSurface::setup_pre_force(int)
{
  // A mesh starts at rest. A later run keeps the node velocities of the last step, as LIGGGHTS 3.8
  // does (its setup only creates the velocity property once); a mesh whose movers were all unfixed
  // is at rest again (LIGGGHTS zeroes the velocities on unfix). A conveyor keeps its own.
  if (moving() ? !mesh_->has_velocity() : !conveyor_ && mesh_->has_velocity()) mesh_->zero_velocity();
  zero_totals();
  rebuilt_this_step_ = false;
}

void FixMeshSurface::zero_totals()
{
  if (!vector_flag) return;
  for (double &v : total_) v = 0.0;
  std::fill(tri_force_.begin(), tri_force_.end(), 0.0);
  contacts_.clear();
  totals_stale_ = true;
}

void FixMeshSurface::pre_force(int)
{
  zero_totals();
  // a node that moved more than skin/2 since the last build forces a rebuild on the next step (§6)
  if (moving() && !rebuilt_this_step_) {
    const double trigger = 0.25 * neighbor->skin * neighbor->skin;
    bool far = false;
    for (int t = 0; t < mesh_->size() && !far; ++t)
      for (int k = 0; k < 3; ++k) {
        const mesh::Vec3 d = mesh::sub(mesh_->node(t, k), nodes_at_build_[t][k]);
        if (mesh::dot(d, d) > trigger) {
          far = true;
          break;
        }
      }
    if (far) next_reneighbor = update->ntimestep + 1;
  }
  rebuilt_this_step_ = false;
}

void FixMeshSurface::final_integrate()
{
  sum_totals();
  if (!wear_) return;
  // this step's wear of every rank's contacts, then added to the total (LIGGGHTS: wear += wear_step)
  std::vector<double> step(wear_step_.size(), 0.0);
  MPI_Allreduce(wear_step_.data(), step.data(), int(step.size()), MPI_DOUBLE, MPI_SUM, world);
  for (std::size_t t = 0; t < step.size(); ++t) wear_total_[t] += step[t];
  std::fill(wear_step_.begin(), wear_step_.end(), 0.0);
}

void FixMeshSurface::sum_totals()
{
  if (!vector_flag || !totals_stale_) return;
  MPI_Allreduce(total_, total_all_, 6, MPI_DOUBLE, MPI_SUM, world);
  totals_stale_ = false;
}

double FixMeshSurface::compute_vector(int i)
{
  sum_totals();  // after setup the sum has not been taken yet (the flag is the same on every rank)
  if (i < 6) return total_all_[i];
  return reference_point()[i - 6];
}

void FixMeshSurface::wall_velocity(int tri, const mesh::Vec3 &bary, double *v) const
{
  const mesh::Vec3 w = mesh_->velocity_at(tri, bary);
  v[0] = w[0];
  v[1] = w[1];
  v[2] = w[2];
}

void FixMeshSurface::add_wall_force(int tri, const double *f, const double *cp)
{
  if (!stress_) return;
  const mesh::Vec3 &p = reference_point();
  const mesh::Vec3 arm{cp[0] - p[0], cp[1] - p[1], cp[2] - p[2]};
  const mesh::Vec3 frc{f[0], f[1], f[2]};
  const mesh::Vec3 tq = mesh::cross(arm, frc);
  for (int k = 0; k < 3; ++k) {
    total_[k] += frc[k];
    total_[3 + k] += tq[k];
    tri_force_[3 * std::size_t(tri) + k] += frc[k];
  }
  if (record_contacts_)
    contacts_.insert(contacts_.end(), {double(tri), f[0], f[1], f[2], cp[0], cp[1], cp[2]});
}

std::vector<double> FixMeshSurface::triangle_forces_all() const
{
  std::vector<double> all(tri_force_.size(), 0.0);
  if (vector_flag) MPI_Allreduce(tri_force_.data(), all.data(), int(all.size()), MPI_DOUBLE, MPI_SUM, world);
  return all;
}

FixMeshSurface *FixMeshSurface::find(LAMMPS *lmp, const std::string &mesh_id, const std::string &caller)
{
  Fix *f = lmp->modify->get_fix_by_id(mesh_id);
  if (!f)
    lmp->error->all(FLERR, caller + ": mesh ID '" + mesh_id + "' does not exist (expected the ID of a fix mesh/surface)");
  auto *m = dynamic_cast<FixMeshSurface *>(f);
  if (!m)
    lmp->error->all(FLERR, caller + ": fix '" + mesh_id + "' is a fix " + f->style +
                               ", not a mesh (expected the ID of a fix mesh/surface)");
  return m;
}

// Restart: the mesh motion state (nodes and the incrementally updated vectors) so a restarted
// moving mesh continues bit for bit, and the accumulated wear per triangle (as LIGGGHTS, whose wear
// is a restart property of the mesh). Layout: [kLayout2, n, state, nwear, wear]; a file of the first
// layout starts with n >= 3 and has no wear.
namespace {
constexpr int kLayout2 = -2;
}

void FixMeshSurface::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  const std::vector<double> state = mesh_->save_state();  // whole state even on a distributed rank (never moved)
  const int marker = kLayout2, n = int(state.size()), nwear = int(wear_total_.size());
  const int size = int(3 * sizeof(int) + (state.size() + wear_total_.size()) * sizeof(double));
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(&marker, sizeof(int), 1, fp);
  fwrite(&n, sizeof(int), 1, fp);
  // an empty vector's data() may be null, which fwrite must not be given (even for 0 items)
  if (!state.empty()) fwrite(state.data(), sizeof(double), state.size(), fp);
  fwrite(&nwear, sizeof(int), 1, fp);
  if (!wear_total_.empty()) fwrite(wear_total_.data(), sizeof(double), wear_total_.size(), fp);
}

void FixMeshSurface::restart(char *buf)
{
  const std::string prefix = std::string("fix ") + style + " (id " + id + ") restart: ";
  int n = 0;
  std::memcpy(&n, buf, sizeof(int));
  const bool layout2 = n == kLayout2;
  if (layout2) std::memcpy(&n, buf + sizeof(int), sizeof(int));
  const char *p = buf + (layout2 ? 2 : 1) * sizeof(int);
  std::vector<double> state(std::size_t(std::max(n, 0)));
  if (!state.empty()) std::memcpy(state.data(), p, state.size() * sizeof(double));
  p += state.size() * sizeof(double);
  try {
    mesh_->restore_state(state);
  } catch (const mesh::MeshError &e) {
    error->all(FLERR, prefix + e.what() + " (define the mesh with the same file and options as before write_restart)");
  }
  int nwear = 0;
  if (layout2) std::memcpy(&nwear, p, sizeof(int));
  if (nwear == 0) return;  // no wear saved: a mesh that starts wearing now starts from zero
  if (!wear_) {
    if (comm->me == 0)
      error->warning(FLERR, prefix + "the restart file holds the wear of this mesh, but 'wear finnie' is off now: the "
                                     "wear is dropped");
    return;
  }
  if (std::size_t(nwear) != wear_total_.size())
    error->all(FLERR, prefix + "the restart file holds the wear of " + std::to_string(nwear) + " triangles, this mesh has " +
                          std::to_string(wear_total_.size()) + " (define the mesh as before write_restart)");
  std::memcpy(wear_total_.data(), p + sizeof(int), wear_total_.size() * sizeof(double));
}

double FixMeshSurface::memory_usage()
{
  return mesh_->memory_bytes() + neighbors_.memory_bytes() + double(tri_force_.capacity()) * sizeof(double) +
         double(nodes_at_build_.capacity()) * sizeof(mesh::TriangleNodes);
}

static void *create_fix_mesh_surface(void *lmp, int narg, char **arg)
{
  return new FixMeshSurface(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_mesh_surface("fix", "mesh/surface", "LIGGGHTS-compatible STL mesh wall",
                                          create_fix_mesh_surface);
static RegisterStyle reg_fix_mesh_surface_planar("fix", "mesh/surface/planar",
                                                 "LIGGGHTS-compatible STL mesh wall (a planar face, e.g. for insertion)",
                                                 create_fix_mesh_surface);
static RegisterStyle reg_fix_mesh_surface_stress("fix", "mesh/surface/stress",
                                                 "LIGGGHTS-compatible STL mesh wall with force/torque output",
                                                 create_fix_mesh_surface);

}  // namespace dembridge
