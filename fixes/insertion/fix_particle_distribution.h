// fix particledistribution/discrete (and /massbased, /numberbased): a discrete mix of particle
// templates for the insertion fixes, LIGGGHTS 3.8 syntax and arithmetic (doc/fix_particledistribution_discrete.md).
// Owns the distribution's random stream, shared by every insert fix that uses it (as in LIGGGHTS).
#pragma once

#include "fix.h"

#include "discrete_distribution.h"

#include <memory>
#include <string>
#include <vector>

namespace dembridge {

class FixParticleDistribution : public LAMMPS_NS::Fix {
 public:
  FixParticleDistribution(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override { return 0; }
  // Restart: the stream's state, and the seed and templates it was drawn for (a changed one is an ERROR).
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;
  const insertion::DiscreteDistribution &distribution() const { return *dist_; }
  insertion::ParkMiller &rng() { return rng_; }
  int seed() const { return seed_; }
  const std::vector<int> &template_seeds() const { return template_seeds_; }
  // group bits an inserted particle joins: this fix's and its templates' (per template index)
  int groupbit_of(int itemplate) const { return groupbit | template_groupbits_[itemplate]; }
  const std::vector<std::string> &template_ids() const { return template_ids_; }
  // The largest radius of the templates of atom type `type` (0 if none): pair styles size their
  // neighbour cut-off with it before the particles exist.
  double max_radius_of_type(int type) const;
  // Throws std::invalid_argument unless insert_seed, this fix's seed and its templates' all differ
  // (LIGGGHTS's check, same message).
  void check_seeds_differ(int insert_seed) const;
  // nullptr if `id` is not a particledistribution/discrete fix
  static FixParticleDistribution *find(LAMMPS_NS::LAMMPS *lmp, const std::string &id);

 private:
  std::unique_ptr<insertion::DiscreteDistribution> dist_;
  insertion::ParkMiller rng_;
  int seed_ = 0;
  std::vector<int> template_seeds_, template_groupbits_;
  std::vector<std::string> template_ids_;
};

}  // namespace dembridge
