#include "lammps_region_view.h"

#include "region.h"

namespace dembridge {

LammpsRegionView::LammpsRegionView(LAMMPS_NS::Region *region) : region_(region)
{
  lo[0] = region->extent_xlo;
  lo[1] = region->extent_ylo;
  lo[2] = region->extent_zlo;
  hi[0] = region->extent_xhi;
  hi[1] = region->extent_yhi;
  hi[2] = region->extent_zhi;
}

bool LammpsRegionView::match(const double *x) const { return region_->match(x[0], x[1], x[2]) != 0; }

bool LammpsRegionView::near_surface(const double *x, double cut) const
{
  double xc[3] = {x[0], x[1], x[2]};
  return (region_->interior ? region_->surface_interior(xc, cut) : region_->surface_exterior(xc, cut)) > 0;
}

}  // namespace dembridge
