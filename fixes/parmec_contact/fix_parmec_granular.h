// fix parmec/granular: LAMMPS glue of Parmec's GRANULAR contact between spheres, between spheres and
// OBSTACLEs and between spheres and MESH bodies (doc/fix_parmec_granular.md). The force law and the
// colour-pair table are in granular_law.h, the obstacles (walls/mesh triangle sets with Parmec's rigid
// motion) in obstacle.h, the MESH bodies' surfaces in mesh_body.h; this file only loops over contacts. Every local sphere evaluates each of its contacts itself (full neighbour list) from the
// contact's state kept in its own record (key: partner tag, or -(obstacle triangle + 1)); the partner does
// the same with the mirrored inputs, so both get exactly opposite forces without reverse communication,
// and the sums run in key order: results do not depend on the decomposition.
#pragma once

#include "granular_law.h"
#include "obstacle.h"
#include "mesh_body.h"
#include "mesh_neighbors.h"

#include "definition_reader.h"
#include "per_atom_state_fix.h"
#include "time_series.h"

#include <array>
#include <string>
#include <unordered_set>
#include <vector>

namespace dembridge {

class FixParmecGranular : public state::PerAtomStateFix {
 public:
  static constexpr int kRecord = 4;  // key, tangential displacement (3)
  // Local output, one row per contact of the last evaluation (each sphere pair once, from its lower tag):
  // tag, partner tag (-1: obstacle; a MESH body's atom ID), colour, partner colour, contact point (3), depth, force on the first
  // body (3), normal force, unit normal n (3, from the partner to the first body), k_n depth, contact area.
  static constexpr int kCols = 17;
  FixParmecGranular(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);

  int setmask() override;
  void init() override;
  void init_list(int id, LAMMPS_NS::NeighList *list) override;
  void setup(int vflag) override;
  int modify_param(int narg, char **arg) override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;
  double compute_vector(int n) override;
  // The obstacles at their current pose (compute parmec/obstacles draws them).
  const std::vector<parmec_contact::Obstacle> &obstacles() const { return obstacles_; }

 private:
  void evaluate(Mode mode) override;
  bool restored_record_fits(int, const double *) const override { return true; }  // contacts come and go

  bool parse_pairing(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
  bool parse_obstacle(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
  bool parse_mesh(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
  void build_bodies();
  void check_mesh_pairs() const;
  void place_bodies(std::vector<int> &skip);
  void apply_body_reactions(const std::vector<double> &reactions);
  bool parse_option(const std::vector<std::string> &tok, std::size_t &i, const std::string &where);
  void build_obstacles();
  int color_of(int i) const;

  state::DefinitionReader reader_;
  parmec_contact::PairingTable pairings_;
  struct ObstacleDef {
    long id = 0;
    std::vector<mesh::TriangleNodes> triangles;
    std::vector<int> colors;
    bool moving = false;
    mesh::Vec3 point{0, 0, 0};
    std::array<std::string, 6> velocity;  // linear x y z, angular x y z: a number or a tseries ID
  };
  std::vector<ObstacleDef> defs_;
  std::unordered_set<long> obstacle_ids_;
  std::vector<parmec_contact::Obstacle> obstacles_;
  std::vector<std::array<springs::TimeSeries, 6>> velocity_;  // replaced by fix_modify ... tseries
  std::vector<int> first_triangle_;                           // global triangle index of each obstacle's first
  std::vector<mesh::MeshNeighbors> candidates_;
  // MESH bodies (keyword 'mesh'): surfaces placed every step from fix parmec/rigid's pose of their atom,
  // replicated on every rank; their triangle keys follow the obstacles' (body_first_)
  struct MeshDef {
    long tag = 0;
    std::vector<mesh::TriangleNodes> triangles;
    std::vector<int> colors;
    mesh::Vec3 centre{0, 0, 0};
  };
  std::vector<MeshDef> mesh_defs_;
  std::unordered_set<long> mesh_tags_;
  std::vector<parmec_contact::MeshBody> bodies_;
  std::vector<int> body_first_;
  std::vector<mesh::MeshNeighbors> body_candidates_;
  LAMMPS_NS::Fix *rigid_ = nullptr;  // fix parmec/rigid: Λ of the MESH bodies
  double body_sums_[6] = {0, 0, 0, 0, 0, 0};  // total force and torque of the spheres on the MESH bodies
  int color_property_ = -1;  // index of i_NAME, or -1: the atom type is the colour
  std::string color_name_ = "type";
  LAMMPS_NS::NeighList *list_ = nullptr;
  double clock_ = 0.0;  // Parmec time t_n of the last committed step (accumulated steps, kept in restart files)
  bool started_ = false;
  bool quirks_ = false;  // 'quirks parmec': Parmec's obstacle start, a contact per triangle, a last separating force
  double counts_[6] = {0, 0, 0, 0, 0, 0};  // local: pair records, obstacle contacts, force on obstacles, MESH contacts
  std::vector<double> scratch_;
};

}  // namespace dembridge
