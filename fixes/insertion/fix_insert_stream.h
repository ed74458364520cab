// fix insert/stream (doc/fix_insert_stream.md): LIGGGHTS 3.8's insertion through a planar mesh face
// at a rate, the particles moving at the normal insertion velocity through the extrusion volume until
// they reach the face. Bit-identical to a one-rank LIGGGHTS run with the same seeds and the same
// particles on any number of ranks (every rank draws the one-rank streams).
#pragma once

#include "fix.h"

#include "insert_keywords.h"
#include "park_miller.h"
#include "stream_insertion.h"

#include <memory>
#include <string>

namespace dembridge {

class FixParticleDistribution;
class FixMeshSurface;

class FixInsertStream : public LAMMPS_NS::Fix {
 public:
  FixInsertStream(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixInsertStream() override;
  int setmask() override;
  void init() override;
  void setup(int vflag) override;
  void pre_exchange() override;
  void end_of_step() override;
  double compute_vector(int i) override;
  // Restart: both streams, the share of the extrusion volume in the box, the next insertion step, the
  // counts (global), and each atom's release state (per atom) (doc "Restart info").
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;
  int pack_restart(int i, double *buf) override;
  void unpack_restart(int nlocal, int nth) override;
  int size_restart(int) override { return kRelease + 1; }
  int maxsize_restart() override { return kRelease + 1; }
  void *extract(const char *name, int &type) override;

  // the release state of each atom migrates and is sorted with it (LAMMPS per-atom callbacks)
  void grow_arrays(int nmax) override;
  void copy_arrays(int i, int j, int delflag) override;
  void set_arrays(int i) override;
  int pack_exchange(int i, double *buf) override;
  int unpack_exchange(int nlocal, double *buf) override;
  double memory_usage() override;

 private:
  // per atom: inserted position (3), insertion step, release step, velocity in the volume (3),
  // velocity at release (3); insertion step 0: not (or no longer) in an extrusion volume of this fix
  static constexpr int kRelease = 11;
  std::string prefix() const;
  void check_face();
  void compute_insertion_properties();
  int count_to_insert();

  insertion::InsertKeywords k_;
  insertion::StreamKeywords s_;
  FixParticleDistribution *dist_ = nullptr;
  FixMeshSurface *face_fix_ = nullptr;
  std::unique_ptr<insertion::StreamFace> face_;
  insertion::StreamSettings settings_;
  insertion::ParkMiller insert_rng_, face_rng_;
  double v_normal_[3] = {0, 0, 0}, p_ref_[3] = {0, 0, 0};
  double vol_lo_[3], vol_hi_[3];  // bounding box of the extrusion volume
  double fraction_ = 0.0;
  bool fraction_done_ = false, setup_done_ = false;
  bool resume_if_more_ = false;      // restart of a finished insertion: go on if the total was raised
  LAMMPS_NS::bigint first_next_ = 0; // next_reneighbor as the constructor set it
  double restart_dt_ = 0.0;          // the timestep of the restart file's run (0: not restarted)
  int insert_every_ = -1;
  long ninsert_ = 0;
  double ninsert_per_ = 0.0;
  LAMMPS_NS::bigint most_recent_ = -1;
  long ninserted_ = 0;
  double massinserted_ = 0.0;
  double extract_radius_ = 0.0;
  double **release_ = nullptr;
};

}  // namespace dembridge
