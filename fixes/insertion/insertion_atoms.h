// What the insertion fixes need from the particles of every rank, and the creation of the particles
// they accepted. Every rank computes the same accepted list (the one-rank streams), so each rank
// creates only those in its sub-domain, with ids in list order after the largest id in use.
#pragma once

#include "lmptype.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {
class LAMMPS;
class Region;
}  // namespace LAMMPS_NS

namespace dembridge {

struct NewSphere {
  double x[3], v[3], omega[3];
  double radius, mass;
  int type, groupbit;
};

// Particles whose centre lies in region (all ranks; sums in id order, so independent of the rank count).
struct RegionContent {
  long count = 0;
  double volume = 0.0, mass = 0.0;
};
RegionContent region_content(LAMMPS_NS::LAMMPS *lmp, LAMMPS_NS::Region *region);

// x, y, z, r of every particle (all ranks) whose centre is within `reach` + its radius of the box
// [lo, hi]; positions remapped into a periodic box as LIGGGHTS does.
std::vector<double> gather_spheres_near(LAMMPS_NS::LAMMPS *lmp, const double *lo, const double *hi, double reach);

class FixPropertyAtomLiggghts;

// A value every new particle gets after the fixes' defaults (LIGGGHTS's set_property NAME V).
struct SetProperty {
  FixPropertyAtomLiggghts *fix = nullptr;  // none: nothing set
  double value = 0.0;
};
// The scalar fix property/atom NAME of `set_property NAME V` (name empty: none); an ERROR starting with
// `who` if there is none.
SetProperty find_set_property(LAMMPS_NS::LAMMPS *lmp, const std::string &name, double value, const std::string &who);

// Creates the spheres of `all` that fall in this rank's sub-domain; returns how many were created on
// all ranks (== all.size()). Ids: largest id in use + 1 + index in `all`.
LAMMPS_NS::bigint create_spheres(LAMMPS_NS::LAMMPS *lmp, const std::vector<NewSphere> &all,
                                 const SetProperty &set = {});

}  // namespace dembridge
