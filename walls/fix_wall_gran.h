// fix wall/gran: LIGGGHTS primitive and mesh walls with the pair styles' contact laws (spec
// liggghts-walls). The geometry is PrimitiveWall / the mesh fixes, the physics gran::ContactLaw,
// the per-contact history WallHistory; this class is the LAMMPS glue. LAMMPS's own
// `fix wall/gran` syntax never reaches it: the creator hands that to the built-in fix.
// Documentation: doc/fix_wall_gran.md.
#pragma once

#include "fix.h"

#include "contact_law.h"
#include "material_table.h"
#include "wall_history.h"
#include "wall_syntax.h"

#include <string>
#include <vector>

namespace dembridge {

class FixMeshSurface;

// One wall contact of the last force evaluation (for compute wall/gran/local).
struct WallContactRecord {
  int atom_index;
  int mesh;          // index in `meshes`, -1 for a primitive wall
  int element;       // triangle id, -1 for a primitive wall
  double delta, Fn;
  double F[3], Ft[3], cp[3];
  double hist[6];    // the contact's history after this evaluation (history_size() values)
};

class FixWallGran : public LAMMPS_NS::Fix {
 public:
  FixWallGran(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixWallGran() override;
  int setmask() override;
  void init() override;
  void setup(int vflag) override;
  void post_force(int vflag) override;

  double memory_usage() override;
  void grow_arrays(int nmax) override;
  void copy_arrays(int i, int j, int delflag) override;
  void set_arrays(int i) override;
  int pack_exchange(int i, double *buf) override;
  int unpack_exchange(int nlocal, double *buf) override;
  int pack_restart(int i, double *buf) override;
  void unpack_restart(int nlocal, int nth) override;
  int size_restart(int i) override;
  int maxsize_restart() override;

  // compute wall/gran/local
  void request_records() { record_ = true; }
  const std::vector<WallContactRecord> &records() const { return records_; }
  int history_size() const { return history_.nvalues(); }
  const walls::WallHistory &history() const { return history_; }
  bool is_mesh_wall() const { return spec_.is_mesh; }

 private:
  std::string me_;  // "fix ID wall/gran" for messages
  walls::WallSpec spec_;
  gran::ContactLaw law_;
  gran::MaterialTable table_;
  walls::WallHistory history_;
  bool record_ = false;
  std::vector<WallContactRecord> records_;

  void check_wall_type(int type, const char *what);
  void primitive_pass(bool update);
  void mesh_pass(bool update);
  void touch(int i, const gran::WallTouch &w, int wall_type, double *hist, bool update, int mesh, int element, double *fpw);

  void init_meshes();
  std::vector<FixMeshSurface *> meshes_;  // looked up again at every init
  LAMMPS_NS::Fix *fix_rigid_ = nullptr;   // body masses replace particle masses (spec §2)
  const int *rigid_body_ = nullptr;       // this step's body index per local atom (-1: none)
  const double *rigid_mass_ = nullptr;    // total mass per body
  void find_rigid_masses();
  std::vector<unsigned char> kept_;  // per atom slot, this pass
};

}  // namespace dembridge
