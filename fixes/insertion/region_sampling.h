// Random points in an insertion region as LIGGGHTS 3.8 draws them (Region::volume_mc,
// generate_random, generate_random_shrinkby_cut), on the region's own stream. LAMMPS-free: the
// region is seen through RegionView.
#pragma once

#include "park_miller.h"

namespace dembridge::insertion {

struct RegionView {
  double lo[3], hi[3];  // the region's bounding box (extent)
  virtual ~RegionView() = default;
  virtual bool match(const double *x) const = 0;
  // LIGGGHTS's match_cut: a surface of the region within `cut` of x (x inside the region)
  virtual bool near_surface(const double *x, double cut) const = 0;
};

struct Box {
  double lo[3], hi[3];
};

struct RegionVolume {
  double global = 0.0, local = 0.0;
  long inside = 0;  // points in the region (0: the volume cannot be computed)
};

// Monte-Carlo volume with ntry points of the bounding box (3 uniforms each); `local` counts only
// points not within `cut` of the surface when all_in (as LIGGGHTS's one-rank run).
RegionVolume volume_mc(const RegionView &region, const Box &box, int ntry, bool all_in, double cut, ParkMiller &rng);

class RegionSampler {
 public:
  // draws in the region's bounding box clipped to `box` (LIGGGHTS: to the rank's sub-domain)
  RegionSampler(const RegionView &region, const Box &box);
  bool empty() const { return empty_; }
  // a point in the region; with cut > 0 also at least `cut` from its surface (all_in yes)
  void draw(double *pos, double cut, ParkMiller &rng) const;

 private:
  const RegionView &region_;
  double lo_[3], diff_[3];
  bool empty_ = false;
};

// LIGGGHTS's Domain::dist_subbox_borders: the smallest distance to a face of the box.
double distance_to_box_faces(const Box &box, const double *x);

}  // namespace dembridge::insertion
