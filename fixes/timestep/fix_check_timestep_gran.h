// fix ID group check/timestep/gran [check_every_time] N fraction_rayleigh fraction_hertz [warn yes|no]
// [error yes|no] [vmax V]: LIGGGHTS 3.8's time-step check. Every N steps: f_ID[1] = dt / Rayleigh
// time, f_ID[2] = dt / Hertz time, f_ID[3] = v_rel,max dt / skin; a WARNING (or with error yes an
// ERROR) when a fraction exceeds its limit, with LIGGGHTS's message text.
#pragma once

#include "fix.h"

#include <string>
#include <vector>

namespace dembridge {

class FixCheckTimestepGran : public LAMMPS_NS::Fix {
 public:
  FixCheckTimestepGran(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  void end_of_step() override;
  double compute_vector(int n) override;

 private:
  void estimate();
  void report(const std::string &msg);
  double mesh_speed_max();

  std::string cmd_;
  double limit_rayleigh_ = 0.0, limit_hertz_ = 0.0, vmax_user_ = 0.0;
  bool warn_ = true, error_ = false;
  std::vector<double> Y_, nu_;  // per type, 1-based
  double rayleigh_time_ = 0.0, hertz_time_ = 0.0, r_min_ = 0.0, v_rel_ = 0.0;
  double fraction_[3] = {0.0, 0.0, 0.0};
};

}  // namespace dembridge
