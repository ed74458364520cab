// A LAMMPS region seen by the LAMMPS-free insertion code (any region style; static regions only).
#pragma once

#include "region_sampling.h"

namespace LAMMPS_NS {
class Region;
}

namespace dembridge {

class LammpsRegionView : public insertion::RegionView {
 public:
  explicit LammpsRegionView(LAMMPS_NS::Region *region);
  bool match(const double *x) const override;
  // LIGGGHTS's Region::match_cut: a contact with the region surface within `cut`
  bool near_surface(const double *x, double cut) const override;

 private:
  LAMMPS_NS::Region *region_;
};

}  // namespace dembridge
