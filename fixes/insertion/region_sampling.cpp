#include "region_sampling.h"

#include <algorithm>
#include <cmath>

namespace dembridge::insertion {

namespace {
bool in_box(const Box &b, const double *x)
{
  return x[0] >= b.lo[0] && x[0] <= b.hi[0] && x[1] >= b.lo[1] && x[1] <= b.hi[1] && x[2] >= b.lo[2] &&
      x[2] <= b.hi[2];
}
}  // namespace

RegionVolume volume_mc(const RegionView &region, const Box &box, int ntry, bool all_in, double cut, ParkMiller &rng)
{
  long n_in = 0, n_local = 0;
  double pos[3];
  for (int i = 0; i < ntry; ++i) {
    for (int d = 0; d < 3; ++d) pos[d] = region.lo[d] + rng.uniform() * (region.hi[d] - region.lo[d]);
    if (!in_box(box, pos)) continue;
    if (!region.match(pos)) continue;
    ++n_in;
    if (!all_in || !region.near_surface(pos, cut)) ++n_local;
  }
  RegionVolume v;
  v.inside = n_local > 0 ? n_in : 0;
  if (v.inside == 0) return v;
  const double vol_bbox =
      (region.hi[0] - region.lo[0]) * (region.hi[1] - region.lo[1]) * (region.hi[2] - region.lo[2]);
  v.global = static_cast<double>(n_in) / static_cast<double>(ntry) * vol_bbox;
  v.local = static_cast<double>(n_local) / static_cast<double>(ntry) * vol_bbox;
  v.local *= (v.global / v.local);  // one rank: the local volume is rescaled to the global one
  return v;
}

RegionSampler::RegionSampler(const RegionView &region, const Box &box) : region_(region)
{
  for (int d = 0; d < 3; ++d) {
    lo_[d] = std::max(region.lo[d], box.lo[d]);
    const double hi = std::min(region.hi[d], box.hi[d]);
    if (lo_[d] >= hi) empty_ = true;
    diff_[d] = hi - lo_[d];
  }
}

void RegionSampler::draw(double *pos, double cut, ParkMiller &rng) const
{
  do {
    pos[0] = lo_[0] + rng.uniform() * diff_[0];
    pos[1] = lo_[1] + rng.uniform() * diff_[1];
    pos[2] = lo_[2] + rng.uniform() * diff_[2];
  } while (!region_.match(pos) || (cut > 0.0 && region_.near_surface(pos, cut)));
}

double distance_to_box_faces(const Box &box, const double *x)
{
  double dlo = std::fabs(box.lo[0] - x[0]), dhi = std::fabs(box.hi[0] - x[0]);
  for (int d = 1; d < 3; ++d) {
    dlo = std::min(dlo, std::fabs(box.lo[d] - x[d]));
    dhi = std::min(dhi, std::fabs(box.hi[d] - x[d]));
  }
  return dlo < dhi ? dlo : dhi;
}

}  // namespace dembridge::insertion
