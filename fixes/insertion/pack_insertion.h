// One insertion event of fix insert/pack and insert/rate/region (LIGGGHTS 3.8's x_v_omega): the
// positions of a list of templates, tried in list order on the region's stream, velocities drawn on
// the insert fix's stream, checked against the overlap grid. LAMMPS-free.
#pragma once

#include "overlap_grid.h"
#include "park_miller.h"
#include "region_sampling.h"

#include <vector>

namespace dembridge::insertion {

struct VelocityRule {
  enum Style { CONSTANT, UNIFORM, GAUSSIAN } style = CONSTANT;
  double v[3] = {0.0, 0.0, 0.0};
  double fluct[3] = {0.0, 0.0, 0.0};
  void draw(ParkMiller &rng, double *out) const;
};

struct PackSettings {
  bool overlapcheck = true;
  bool all_in = false;
  bool check_border = true;  // check_dist_from_subdomain_border (LIGGGHTS default yes)
  VelocityRule vel;
};

struct Placed {
  double x[3], v[3];
  int template_index;
};

// Places list[0..] in order until one cannot be placed within maxtry tries in all (the placed ones
// are always a prefix of the list). radii[i] is the radius of template i. Placed spheres are added
// to `grid` (when overlapcheck).
std::vector<Placed> place(const std::vector<int> &list, const std::vector<double> &radii, const RegionSampler &sampler,
                          const Box &box, const PackSettings &settings, int maxtry, ParkMiller &region_rng,
                          ParkMiller &insert_rng, OverlapGrid &grid);

}  // namespace dembridge::insertion
