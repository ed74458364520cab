// fix wall/gran: LIGGGHTS primitive and mesh walls with the pair styles' contact laws (spec
// liggghts-walls). The geometry is PrimitiveWall / the mesh fixes, the physics gran::ContactLaw;
// the per-contact history is a record list per atom (fixes/state: it follows the atom through
// migration, sorting, deletion and restart files); this class is the LAMMPS glue. LAMMPS's own
// `fix wall/gran` syntax never reaches it: the creator hands that to the built-in fix.
// Documentation: doc/fix_wall_gran.md.
#pragma once

#include "contact_law.h"
#include "material_table.h"
#include "per_atom_records_fix.h"
#include "wall_syntax.h"

#include <cstdint>
#include <string>
#include <vector>

namespace dembridge {

class FixMeshSurface;
namespace mesh {
class TriangleMesh;
}

// One wall contact of the last force evaluation (for compute wall/gran/local).
struct WallContactRecord {
  int atom_index;
  int mesh;          // index in `meshes`, -1 for a primitive wall
  int element;       // triangle id, -1 for a primitive wall
  double delta, Fn;
  double F[3], Ft[3], cp[3];
  double hist[6];    // the contact's history after this evaluation (history_size() values)
};

// The wall contacts of an atom (spec §3, §4.5): one record each, [key, history_size() values], in the
// order they began. Key: 0 for a primitive wall, mesh index * 2^32 + triangle for a mesh wall.
class FixWallGran : public state::PerAtomRecordsFix {
 public:
  FixWallGran(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void setup(int vflag) override;
  void post_force(int vflag) override;
  double memory_usage() override;  // the contact records (PerAtomRecordsFix) and this pass's per-slot flags

  // compute wall/gran/local
  void request_records() { record_ = true; }
  const std::vector<WallContactRecord> &records() const { return contact_rows_; }
  int history_size() const { return records_.record_size() - 1; }
  bool is_mesh_wall() const { return spec_.is_mesh; }
  // The meshes of a mesh wall (valid after init()); fix check/timestep/gran reads their speeds.
  const std::vector<FixMeshSurface *> &meshes() const { return meshes_; }

 private:
  // The record size follows from the model: the arguments are parsed before the base is built.
  FixWallGran(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg, walls::WallSpec spec);
  static walls::WallSpec parse(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  walls::WallSpec spec_;
  gran::ContactLaw law_;
  gran::MaterialTable table_;
  int capacity_ = 1;  // wall contacts one atom may have at a time
  bool record_ = false;
  std::vector<WallContactRecord> contact_rows_;

  void check_restored(int i) override;

  void check_wall_type(int type, const char *what);
  void primitive_pass(bool update);
  void mesh_pass(bool update);
  [[noreturn]] void undefined_normal(int i, int mesh, int element);
  void touch(int i, const gran::WallTouch &w, int wall_type, double *hist, bool update, int mesh, int element, double *fpw);

  void init_meshes();
  int local_tri(const mesh::TriangleMesh &mesh, double key);
  std::vector<FixMeshSurface *> meshes_;  // looked up again at every init
  LAMMPS_NS::Fix *fix_rigid_ = nullptr;   // body masses replace particle masses (spec §2)
  const int *rigid_body_ = nullptr;       // this step's body index per local atom (-1: none)
  const double *rigid_mass_ = nullptr;    // total mass per body
  void find_rigid_masses();
  std::vector<unsigned char> kept_;  // per slot of the active atoms, this pass
  std::vector<int> active_, has_candidates_;  // mesh_pass: the atoms with candidate triangles
  // what active_ was found for: the meshes' candidate builds and the local atom count
  std::vector<std::uint64_t> active_builds_;
  int active_nlocal_ = -1;
  bool find_active_atoms();
};

}  // namespace dembridge
