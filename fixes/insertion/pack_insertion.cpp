#include "pack_insertion.h"

namespace dembridge::insertion {

void VelocityRule::draw(ParkMiller &rng, double *out) const
{
  for (int d = 0; d < 3; ++d) out[d] = v[d];
  if (style == UNIFORM)
    for (int d = 0; d < 3; ++d) out[d] = v[d] + fluct[d] * 2.0 * (rng.uniform() - 0.50);
  else if (style == GAUSSIAN)
    for (int d = 0; d < 3; ++d) out[d] = v[d] + fluct[d] * rng.gaussian();
}

std::vector<Placed> place(const std::vector<int> &list, const std::vector<double> &radii, const RegionSampler &sampler,
                          const Box &box, const PackSettings &settings, int maxtry, ParkMiller &region_rng,
                          ParkMiller &insert_rng, OverlapGrid &grid)
{
  std::vector<Placed> placed;
  const int n = static_cast<int>(list.size());
  Placed p;
  if (!settings.overlapcheck) {
    for (int k = 0; k < n; ++k) {
      const double r = radii[list[k]];
      sampler.draw(p.x, settings.all_in ? r : 0.0, region_rng);
      settings.vel.draw(insert_rng, p.v);
      p.template_index = list[k];
      placed.push_back(p);
    }
    return placed;
  }
  int ntry = 0;
  while (ntry < maxtry && static_cast<int>(placed.size()) < n) {
    const int t = list[placed.size()];
    const double r = radii[t];
    bool ok = false;
    while (!ok && ntry < maxtry) {
      do {
        sampler.draw(p.x, settings.all_in ? r : 0.0, region_rng);
        ++ntry;
      } while (settings.check_border && ntry < maxtry && distance_to_box_faces(box, p.x) < r);
      if (ntry == maxtry) break;  // LIGGGHTS gives up here even if this last point would fit
      settings.vel.draw(insert_rng, p.v);
      ok = !grid.overlaps(p.x, r);
    }
    if (ok) {
      grid.add(p.x, r);
      p.template_index = t;
      placed.push_back(p);
    }
  }
  return placed;
}

}  // namespace dembridge::insertion
