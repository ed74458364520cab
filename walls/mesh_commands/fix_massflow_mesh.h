// fix ID group massflow/mesh mesh MESH_ID vec_side vx vy vz | point_at_outlet px py pz [inside_out]
// [count once|multiple] [sum_property NAME] [file F | append F] [writeTime] [screen yes|no]:
// LIGGGHTS 3.8's mass and particle count through a mesh face. A particle near the mesh (one of the
// mesh's wall-contact candidates) is counted when it passes from the side opposite vec_side to the
// vec_side side (or, with point_at_outlet, when the triangle it touches lies between it and the point).
// [delete_atoms yes]. Global vector: mass, count, mass rate, count rate (since the last output), mass and
// count deleted, the sum of sum_property.
#pragma once

#include "fix.h"
#include "lmptype.h"

#include <cstdio>
#include <string>
#include <vector>

namespace dembridge {

class FixMeshSurface;
class FixPropertyAtomLiggghts;

class FixMassflowMesh : public LAMMPS_NS::Fix {
 public:
  FixMassflowMesh(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixMassflowMesh() override;
  void post_constructor() override;
  int setmask() override;
  void init() override;
  void setup(int vflag) override;
  void post_integrate() override;
  void pre_exchange() override;
  double compute_vector(int i) override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

 private:
  void count_particle(int i, int tri, double dot, double &mass, int &n, double &prop);
  void write_line(FILE *fp, int i);

  std::string cmd_, mesh_id_, counter_id_, property_name_;
  FixMeshSurface *mesh_ = nullptr;
  FixPropertyAtomLiggghts *counter_ = nullptr, *property_ = nullptr;
  double side_[3] = {0, 0, 0}, outlet_[3] = {0, 0, 0}, pref_[3] = {0, 0, 0}, nvec_[3] = {0, 0, 0};
  bool point_at_outlet_ = false, inside_out_ = false, once_ = false, write_time_ = false, screen_ = false;
  FILE *fp_ = nullptr;
  double mass_ = 0.0, property_sum_ = 0.0, mass_last_ = 0.0, t_count_ = 0.0, delta_t_ = 0.0;
  long nparticles_ = 0, nparticles_last_ = 0;
  bool reset_t_count_ = true;
  // delete_atoms yes: the particles counted since the last re-neighbouring, deleted at the next one
  // (pre_exchange), in LIGGGHTS's order: by step, then by the triangle they were counted at
  bool delete_atoms_ = false;
  struct Mark {
    int tri, local;
    LAMMPS_NS::tagint tag;
  };
  std::vector<Mark> marks_step_;
  std::vector<LAMMPS_NS::tagint> to_delete_;
  double mass_deleted_ = 0.0;
  long nparticles_deleted_ = 0;
};

}  // namespace dembridge
