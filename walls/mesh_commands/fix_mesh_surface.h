// fix mesh/surface and fix mesh/surface/stress: an STL triangle mesh wall (doc/fix_mesh_surface.md,
// doc/fix_mesh_surface_stress.md). The geometry lives in walls/mesh/ (LAMMPS-free); this is glue.
//
// CONTRACT for a wall fix (fix wall/gran ... mesh n_meshes N meshes ID ...):
//  * Find the mesh:  FixMeshSurface *m = FixMeshSurface::find(lmp, id, "fix wall/gran");
//    (errors with the caller's name if the ID is unknown or not a mesh fix).
//  * Only local atoms interact with the mesh (no ghosts needed). A static mesh is distributed:
//    each rank keeps the triangles its atoms can reach (see keep_whole()); local triangle ids
//    ascend in file order, m->mesh().global_id(t) is the file-order id to key history and output.
//  * Candidates: m->candidates(i) / m->ncandidates(i) for local atom i, triangle ids ascending.
//    Rebuilt by this fix in (setup_)post_neighbor for all local atoms, so they are valid in
//    post_force of every step until the next re-neighbouring. Process them in that order: it is
//    LIGGGHTS's force order per particle (spec liggghts-walls §4.5).
//  * Geometry: m->closest(tri, x, radius) gives dist_minus_r, delta (wall point - centre), bary,
//    kind (spec §4.4). m->mesh().coplanar_node_neighbors(a, b) for the §4.5 de-duplication.
//  * Wall velocity at the contact: m->wall_velocity(tri, bary, v) (zero for a static mesh).
//  * Material type of the wall: m->wall_type().
//  * Force on the mesh (§8): after adding a contact to f_i, call
//      if (m->stress_on() && (mask[i] & m->groupbit)) m->add_wall_force(tri, frc, cp);
//    with frc = -(f_i after - f_i before) and cp = x_i + delta. This fix zeroes the totals in
//    pre_force, MPI-sums them in final_integrate (and after setup), and serves f_ID[1..9].
//  * Shape changes: the wall fix must not keep pointers into the mesh across steps; the triangle
//    count never changes after construction.
#pragma once

#include "fix.h"

#include "mesh_box_extent.h"
#include "mesh_neighbors.h"
#include "mesh_placement.h"
#include "triangle_contact.h"
#include "triangle_mesh.h"

#include <memory>
#include <string>
#include <vector>

namespace dembridge {

class FixMoveMesh;

class FixMeshSurface : public LAMMPS_NS::Fix {
 public:
  FixMeshSurface(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixMeshSurface() override;
  int setmask() override;
  void init() override;
  void setup_pre_exchange() override;
  void pre_exchange() override;
  void setup_pre_neighbor() override;
  void setup_post_neighbor() override;
  void setup_pre_force(int vflag) override;
  void pre_neighbor() override;
  void post_neighbor() override;
  void pre_force(int vflag) override;
  void final_integrate() override;
  double compute_vector(int i) override;
  void post_run() override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;
  double memory_usage() override;

  // ---- API for wall fixes (see the contract above)
  static FixMeshSurface *find(LAMMPS_NS::LAMMPS *lmp, const std::string &id, const std::string &caller);
  const mesh::TriangleMesh &mesh() const { return *mesh_; }
  int wall_type() const { return wall_type_; }
  bool moving() const { return !movers_.empty() || external_driver_; }
  // A fix that moves the mesh itself (fix mbdyn ... node mesh ID) marks it as moving, so the
  // candidates use the full skin and the geometry is refreshed at re-neighbouring (§6, §7.3).
  void drive_externally()
  {
    keep_whole();
    external_driver_ = true;
  }
  bool driven_externally() const { return external_driver_; }
  // fix mbdyn ... mapping: keep every add_wall_force of the step (this rank's, from the last
  // pre_force on) as triangle, force, contact point, for the distribution to the vertices.
  void record_contacts() { record_contacts_ = true; }
  const std::vector<double> &contacts() const { return contacts_; }
  int ncandidates(int i) const { return i < neighbors_.nparticles() ? neighbors_.count(i) : 0; }
  const int *candidates(int i) const { return neighbors_.begin(i); }
  std::uint64_t candidate_builds() const { return neighbors_.builds(); }  // changes whenever the lists may have
  mesh::TriangleContact closest(int tri, const double *x, double radius) const
  {
    return mesh::resolve_contact(*mesh_, tri, {x[0], x[1], x[2]}, radius);
  }
  void wall_velocity(int tri, const mesh::Vec3 &bary, double *v) const;
  bool stress_on() const { return stress_; }
  void add_wall_force(int tri, const double *f_on_mesh, const double *contact_point);
  // wear finnie: one contact's wear this step (x, v: the particle; cp: contact point; f: contact force)
  bool wear_on() const { return wear_; }
  void add_wear(int tri, const double *x, const double *v, const double *cp, const double *v_wall, const double *f,
                int atom_type);
  // Accumulated wear per triangle (same on every rank; empty without wear finnie).
  const std::vector<double> &wear() const { return wear_total_; }

  // ---- API for fix move/mesh and the mesh dumps
  // A user of every triangle (movers, drivers, dumps, massflow, insertion faces) keeps the mesh whole
  // on every rank from now on (it is read again from the file if this rank kept a part).
  void keep_whole();
  mesh::TriangleMesh &mesh_for_motion()
  {
    keep_whole();
    return *mesh_;
  }
  // Position of a fix move/mesh among the movers of this mesh in fix order (0 = first, which
  // zeroes the node velocities each step), -1 if not one of them. Valid after init().
  int mover_rank(const FixMoveMesh *mover) const;
  // Per-triangle force on the mesh summed over ranks (collective; zeros without stress).
  std::vector<double> triangle_forces_all() const;
  const mesh::Vec3 &reference_point() const { return mesh_->attached_point(ref_point_); }

 private:
  std::unique_ptr<mesh::TriangleMesh> mesh_;
  // how the mesh was built, to read it again when a rank needs triangles it dropped
  std::string file_;
  mesh::MeshOptions opt_;
  std::vector<mesh::PlacementOp> ops_;
  std::uint64_t digest_ = 0;
  struct Conveyor {
    bool linear;
    mesh::Vec3 v, origin, axis;
    double omega;
  } conveyor_args_{};
  bool distribute_ = true;   // 'distribute yes' (default)
  bool keep_whole_ = false;  // keep_whole() was asked for
  bool split_ = false;       // kept_lo_/kept_hi_ bound what this rank keeps
  mesh::Vec3 kept_lo_{}, kept_hi_{};
  MeshExtent split_extent_;          // the nodes' extent when the mesh was last whole (a part is kept)
  ShrinkWrapAroundMeshes box_wrap_;  // open around reset_box (the first mesh fix does it for all)
  int outside_ = 0;               // check_domain() of the whole mesh, for the warnings of later runs
  bool crosses_periodic_ = false;
  mesh::MeshNeighbors neighbors_;
  std::vector<FixMoveMesh *> movers_;  // in fix order, found in init()
  int wall_type_ = 0;
  bool stress_ = false;
  bool wear_ = false;
  std::vector<double> wear_total_, wear_step_;  // per triangle: summed over ranks / this rank's, this step
  std::vector<double> k_finnie_;                // per particle type (1-based), for this mesh's wall type
  int ref_point_ = -1;
  double total_[6] = {0, 0, 0, 0, 0, 0};  // force, torque about the reference point (this rank)
  double total_all_[6] = {0, 0, 0, 0, 0, 0};
  std::vector<double> tri_force_;          // per triangle, this rank
  std::vector<mesh::TriangleNodes> nodes_at_build_;
  bool rebuilt_this_step_ = false;
  bool external_driver_ = false;
  bool record_contacts_ = false;
  std::vector<double> contacts_;  // record_contacts(): 7 per contact of this step, this rank
  bool conveyor_ = false;       // surface_vel / surface_ang_vel
  bool totals_stale_ = false;   // totals changed since the last MPI sum (same on every rank)

  void build_candidates();
  std::unique_ptr<mesh::TriangleMesh> read_mesh() const;
  void reload_whole();
  void fit_to_reach(double s);
  void log_distribution();
  void zero_totals();
  void sum_totals();
  void remember_nodes();
  void check_domain();
  MeshExtent extent() const;
  bool leads_box_wrap() const;
  MeshExtent all_meshes_extent() const;
  void open_box_wrap();
  void close_box_wrap() { box_wrap_.close(domain); }
  void set_surface_velocity();
};

}  // namespace dembridge
