#include "fix_massflow_mesh.h"

#include "fix_mesh_surface.h"
#include "lammps_atom_vec.h"
#include "fix_property_atom_liggghts.h"
#include "math/vec3.h"
#include "mesh_args.h"
#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "modify.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace dembridge {

using math::dot3;

namespace {

// LIGGGHTS's planarity of a face: every triangle parallel to the first (the mesh's coplanarity limit).
bool is_planar(const mesh::TriangleMesh &m)
{
  const mesh::Vec3 &n0 = m.normal(0);
  for (int t = 1; t < m.size(); ++t)
    if (std::fabs(mesh::dot(m.normal(t), n0)) < m.options().curvature) return false;
  for (int t = 0; t < m.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (std::fabs(mesh::dot(mesh::sub(m.node(t, k), m.node(0, 0)), n0)) > 1e-10 * std::sqrt(m.area(0))) return false;
  return true;
}
}  // namespace

FixMassflowMesh::FixMassflowMesh(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  cmd_ = std::string("fix massflow/mesh (id ") + id + ")";
  MeshArgs a(lmp, cmd_, narg, arg, 3);
  std::string file;
  bool append = false;
  while (!a.done()) {
    const std::string key = a.word("keyword");
    if (key == "vec_side") {
      const mesh::Vec3 v = a.nonzero_vec3("vec_side");
      for (int k = 0; k < 3; ++k) side_[k] = v[k];
    } else if (key == "mesh") {
      mesh_id_ = a.word("mesh");
      mesh_ = FixMeshSurface::find(lmp, mesh_id_, cmd_ + ": mesh");
    } else if (key == "sum_property") {
      property_name_ = a.word("sum_property");
    } else if (key == "count") {
      const std::string v = a.word("count");
      if (v != "once" && v != "multiple") a.fail("count", "expected 'once' or 'multiple', got '" + v + "'");
      once_ = v == "once";
    } else if (key == "writeTime") {
      write_time_ = true;
    } else if (key == "point_at_outlet") {
      const mesh::Vec3 p = a.vec3("point_at_outlet");
      for (int k = 0; k < 3; ++k) outlet_[k] = p[k];
      point_at_outlet_ = true;
    } else if (key == "inside_out") {
      if (!point_at_outlet_) a.fail("inside_out", "has no meaning without 'point_at_outlet' before it");
      inside_out_ = true;
    } else if (key == "file" || key == "append") {
      file = a.word(key);
      append = key == "append";
    } else if (key == "screen") {
      screen_ = a.yes_no("screen");
    } else if (key == "delete_atoms") {
      delete_atoms_ = a.yes_no("delete_atoms");
    } else {
      a.fail("'" + key + "'", "unknown keyword (expected mesh, vec_side, point_at_outlet, inside_out, count, "
                              "sum_property, file, append, writeTime, screen, delete_atoms)");
    }
  }
  if (!once_ && point_at_outlet_) a.fail("point_at_outlet", "requires 'count once'");
  if (dot3(side_, side_) == 0.0 && !point_at_outlet_) a.fail("vec_side", "missing (expected 'vec_side vx vy vz' or 'point_at_outlet')");
  if (!mesh_) a.fail("mesh", "missing (expected 'mesh ID' of a fix mesh/surface)");
  mesh_->keep_whole();  // the planarity and side tests look at every triangle

  const mesh::TriangleMesh &m = mesh_->mesh();
  for (int k = 0; k < 3; ++k) {
    pref_[k] = m.node(0, 0)[k];
    nvec_[k] = m.normal(0)[k];
  }
  const double d = dot3(nvec_, side_);
  if (std::fabs(d) < 1e-6 && !point_at_outlet_)
    a.fail("vec_side", "is in or too close to the mesh plane; change it");
  else if (d < 0.)
    for (double &c : nvec_) c = -c;

  if (!file.empty()) {
    // as LIGGGHTS: one file per rank (F.rank) on more than one rank
    const std::string name = comm->nprocs > 1 ? file + "." + std::to_string(comm->me) : file;
    fp_ = std::fopen(name.c_str(), append ? "a" : "w");
    if (!fp_) a.fail(append ? "append" : "file", "cannot open '" + name + "' for writing");
    std::fprintf(fp_, "# ID");
    if (write_time_) std::fprintf(fp_, " time ");
    std::fprintf(fp_, " diameter x y z u v w");
    std::fprintf(fp_, "  (ex ey ez, color)\n");
    std::fflush(fp_);
  }
  restart_global = 1;
  vector_flag = 1;
  size_vector = property_name_.empty() ? 6 : 7;
  global_freq = 1;
  extvector = 1;
}

FixMassflowMesh::~FixMassflowMesh()
{
  if (fp_) std::fclose(fp_);
  if (!counter_id_.empty() && modify->get_fix_by_id(counter_id_)) modify->delete_fix(counter_id_);
}

// The per-particle side flag, as LIGGGHTS: -1 not yet seen near the mesh, 0 on the far side,
// 1 on the vec_side side, 2 counted (count once).
void FixMassflowMesh::post_constructor()
{
  counter_id_ = std::string("massflow_") + id;
  modify->add_fix(counter_id_ + " all property/atom " + counter_id_ + " scalar yes no no -1.");
  counter_ = FixPropertyAtomLiggghts::find(lmp, counter_id_);
}

int FixMassflowMesh::setmask() { return POST_INTEGRATE | (delete_atoms_ ? PRE_EXCHANGE : 0); }

void FixMassflowMesh::init()
{
  if (!atom->rmass_flag) error->all(FLERR, cmd_ + ": requires atoms that have a per-particle mass");
  if (delete_atoms_ && atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, cmd_ + ": delete_atoms yes requires an atom map (add 'atom_modify map array', as LIGGGHTS asks)");
  mesh_ = FixMeshSurface::find(lmp, mesh_id_, cmd_ + ": mesh");
  mesh_->keep_whole();
  counter_ = FixPropertyAtomLiggghts::find(lmp, counter_id_);
  if (!property_name_.empty()) {
    property_ = FixPropertyAtomLiggghts::find(lmp, property_name_);
    if (!property_ || !property_->is_scalar())
      error->all(FLERR, cmd_ + ": sum_property: '" + property_name_ +
                            "' is not a scalar fix property/atom (define it with fix property/atom NAME scalar ...)");
  }
}

void FixMassflowMesh::setup(int)
{
  if (!point_at_outlet_ && !is_planar(mesh_->mesh()))
    error->all(FLERR, cmd_ + ": requires a planar face mass flow measurement or using 'point_at_outlet'");
}

void FixMassflowMesh::write_line(FILE *fp, int i)
{
  const double *x = atom->x[i], *v = atom->v[i];
  std::fprintf(fp, "%d", int(atom->tag[i]));
  if (write_time_) std::fprintf(fp, "  %4.4g ", update->dt * double(update->ntimestep));
  std::fprintf(fp, " %4.4g %4.4g %4.4g %4.4g %4.4g %4.4g %4.4g", 2. * atom->radius[i], x[0], x[1], x[2], v[0], v[1], v[2]);
  std::fprintf(fp, "\n");
  std::fflush(fp);
}

void FixMassflowMesh::count_particle(int i, int tri, double dot, double &mass, int &n, double &prop)
{
  double &c = counter_->values()[i];
  if (c == -1.0) {  // first time near the mesh: only note the side
    c = (dot <= 0.) ? 0. : 1.;
    return;
  }
  if (dot > 0.) {
    if (c == 0.0) {
      mass += atom->rmass[i];
      ++n;
      if (property_) prop += property_->values()[i];
      if (screen_ && screen)
        std::fprintf(screen, " %d %4.4g %4.4g %4.4g %4.4g %4.4g %4.4g %4.4g \n ", int(atom->tag[i]), 2. * atom->radius[i],
                     atom->x[i][0], atom->x[i][1], atom->x[i][2], atom->v[i][0], atom->v[i][1], atom->v[i][2]);
      if (fp_) write_line(fp_, i);
      if (delete_atoms_) {  // as LIGGGHTS: the flag starts again (-1); the particle goes at the next re-neighbouring
        c = -1.;
        marks_step_.push_back({tri, i, atom->tag[i]});
        return;
      }
    }
    if (!delete_atoms_) c = once_ ? 2. : 1.;  // LIGGGHTS leaves the flag of a deleting fix alone here
  } else {
    c = 0.;
  }
}

// LIGGGHTS loops the triangles and each triangle's nearby particles; a particle's state changes per
// (triangle, particle) visit, so here each particle visits its candidate triangles in ascending order.
void FixMassflowMesh::post_integrate()
{
  t_count_ += update->dt;
  if (!reset_t_count_) {
    nparticles_last_ = nparticles_;
    mass_last_ = mass_;
    reset_t_count_ = true;
  }
  double mass_this = 0.0, prop_this = 0.0;
  int n_this = 0;
  const int *mask = atom->mask;
  double **x = atom->x;
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(mask[i] & groupbit)) continue;
    const int nc = mesh_->ncandidates(i);
    const int *cand = mesh_->candidates(i);
    for (int k = 0; k < nc; ++k) {
      if (counter_->values()[i] == 2.0) break;
      double dot = 0.0;
      if (point_at_outlet_) {
        const mesh::TriangleContact tc = mesh_->closest(cand[k], x[i], atom->radius[i]);
        if (!(tc.dist_minus_r < atom->radius[i])) continue;
        const double to_particle[3] = {x[i][0] - outlet_[0], x[i][1] - outlet_[1], x[i][2] - outlet_[2]};
        dot = dot3(tc.delta.data(), to_particle);
        if (inside_out_) dot = -dot;
      } else {
        const double delta[3] = {x[i][0] - pref_[0], x[i][1] - pref_[1], x[i][2] - pref_[2]};
        dot = dot3(delta, nvec_);
      }
      count_particle(i, cand[k], dot, mass_this, n_this, prop_this);
    }
  }
  if (!marks_step_.empty()) {
    // LIGGGHTS marks triangle by triangle, each triangle's particles in its bin order; ascending local
    // index is that order for particles in one bin
    std::stable_sort(marks_step_.begin(), marks_step_.end(),
                     [](const Mark &a, const Mark &b) { return a.tri != b.tri ? a.tri < b.tri : a.local < b.local; });
    for (const Mark &m : marks_step_) to_delete_.push_back(m.tag);
    marks_step_.clear();
  }
  double sums[3] = {mass_this, prop_this, double(n_this)}, all[3] = {0.0, 0.0, 0.0};
  MPI_Allreduce(sums, all, 3, MPI_DOUBLE, MPI_SUM, world);  // one reduction per step (counts exact in a double)
  mass_ += all[0];
  nparticles_ += long(all[2]);
  property_sum_ += all[1];
}

// delete_atoms yes: before the exchange and the neighbour build of a re-neighbouring step, as LIGGGHTS
// (the last local particle takes the deleted one's place, in the order they were counted).
void FixMassflowMesh::pre_exchange()
{
  double mass = 0.0;
  int n = 0;
  for (const tagint tag : to_delete_) {
    const int i = atom->map(tag);
    if (i < 0 || i >= atom->nlocal) continue;  // counted twice before a re-neighbouring: already gone
    mass += atom->rmass[i];
    ++n;
    const int last = atom->nlocal - 1;
    atom->map_one(tag, -1);
    if (i != last) {
      atom->avec->copy(last, i, 1);
      atom->map_one(atom->tag[i], i);
    }
    atom->nlocal--;
  }
  to_delete_.clear();
  double local[2] = {mass, double(n)}, all[2] = {0.0, 0.0};
  MPI_Allreduce(local, all, 2, MPI_DOUBLE, MPI_SUM, world);
  mass_deleted_ += all[0];
  nparticles_deleted_ += long(all[1]);
  if (all[1] == 0.0) return;
  const bigint nlocal = atom->nlocal;
  MPI_Allreduce(&nlocal, &atom->natoms, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  atom->nghost = 0;
  atom->map_init();
  atom->map_set();
}

double FixMassflowMesh::compute_vector(int index)
{
  if (reset_t_count_) {
    delta_t_ = t_count_;
    t_count_ = 0.;
    reset_t_count_ = false;
  }
  if (index == 0) return mass_;
  if (index == 1) return double(nparticles_);
  if (index == 2) return delta_t_ == 0. ? 0. : (mass_ - mass_last_) / delta_t_;
  if (index == 3) return delta_t_ == 0. ? 0. : double(nparticles_ - nparticles_last_) / delta_t_;
  if (index == 4) return mass_deleted_;
  if (index == 5) return double(nparticles_deleted_);
  if (index == 6 && property_) return property_sum_;
  return 0.;
}

void FixMassflowMesh::write_restart(FILE *fp)
{
  const double list[6] = {mass_, t_count_, mass_last_, double(nparticles_last_), mass_deleted_, double(nparticles_deleted_)};
  if (comm->me == 0) {
    const int size = int(sizeof list);
    std::fwrite(&size, sizeof(int), 1, fp);
    std::fwrite(list, sizeof(double), 6, fp);
  }
}

// As LIGGGHTS, the count itself is not in the restart file (only the mass).
void FixMassflowMesh::restart(char *buf)
{
  double list[6];
  std::memcpy(list, buf, sizeof list);
  mass_ = list[0];
  t_count_ = list[1];
  mass_last_ = list[2];
  nparticles_last_ = long(list[3]);
  mass_deleted_ = list[4];
  nparticles_deleted_ = long(list[5]);
}

static RegisterStyle reg_massflow("fix", "massflow/mesh", "LIGGGHTS mass flow through a mesh face",
                                  create_fix<FixMassflowMesh>);

}  // namespace dembridge
