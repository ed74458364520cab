// fix insert/pack and insert/rate/region (doc/fix_insert_pack.md, doc/fix_insert_rate_region.md):
// LIGGGHTS 3.8's insertion into a region up to a volume fraction, a particle count or a mass, or at a
// rate up to a total, bit-identical to a one-rank LIGGGHTS run with the same seeds
// and the same particles on any number of ranks (every rank draws the one-rank streams).
#pragma once

#include "fix.h"

#include "insert_keywords.h"
#include "park_miller.h"

#include <memory>
#include <string>

namespace LAMMPS_NS {
class Region;
}

namespace dembridge {

class FixParticleDistribution;

class FixInsertPack : public LAMMPS_NS::Fix {
 public:
  FixInsertPack(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void setup(int vflag) override;
  void pre_exchange() override;
  double compute_vector(int i) override;
  // Restart: both streams, the region volume, the next insertion step, the counts (doc "Restart info").
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;
  // "radius", type: the largest radius this fix inserts of that type (pair styles size their
  // neighbour cut-off with it before the particles exist, as for fix pour)
  void *extract(const char *name, int &type) override;

 private:
  std::string prefix() const;
  void compute_region_volume();
  int count_to_insert();
  void schedule_next(bool inserted);

  const bool rate_;  // insert/rate/region
  insertion::InsertKeywords k_;
  insertion::PackKeywords p_;
  FixParticleDistribution *dist_ = nullptr;
  LAMMPS_NS::Region *region_ = nullptr;
  insertion::ParkMiller insert_rng_, region_rng_;
  double region_volume_ = 0.0, region_volume_local_ = 0.0, insertion_ratio_ = 0.0;
  bool setup_done_ = false;
  bool volume_done_ = false;         // region_volume_ drawn (in setup or read from a restart file)
  bool resume_if_more_ = false;      // restart of a finished insertion: go on if the total was raised
  LAMMPS_NS::bigint first_next_ = 0; // next_reneighbor as the constructor set it
  LAMMPS_NS::bigint most_recent_ = -1;
  long ninserted_ = 0;
  long ninsert_ = 0;          // insert/rate/region: the total to insert
  double ninsert_per_ = 0.0;  // insert/rate/region: particles per insertion
  double massinserted_ = 0.0;
  double extract_radius_ = 0.0;
};

}  // namespace dembridge
