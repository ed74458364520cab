#include "mesh_box_extent.h"

#include "domain.h"

#include <algorithm>

namespace dembridge {
namespace {
constexpr int kShrinkWrapMin = 3;  // Domain::boundary code of 'm'

// Domain::small (the wrap margin, 1e-4 of the initial box) is protected; a derived class may name it.
struct DomainMargin : LAMMPS_NS::Domain {
  static const double *of(const LAMMPS_NS::Domain *d) { return d->*(&DomainMargin::small); }
};
}  // namespace

void widen_shrink_wrap_minimum(LAMMPS_NS::Domain *domain, const mesh::TriangleMesh &m, long long natoms)
{
  if (domain->triclinic || m.size() == 0) return;
  mesh::Vec3 lo = m.node(0, 0), hi = lo;
  for (int t = 0; t < m.size(); ++t)
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], m.node(t, k)[d]);
        hi[d] = std::max(hi[d], m.node(t, k)[d]);
      }
  // LIGGGHTS: box = min(atoms, nodes) - margin; min() commutes with the (monotone) rounded subtraction
  const double *margin = DomainMargin::of(domain);
  double *min_lo[3] = {&domain->minxlo, &domain->minylo, &domain->minzlo};
  double *min_hi[3] = {&domain->minxhi, &domain->minyhi, &domain->minzhi};
  for (int d = 0; d < 3; ++d) {
    if (domain->boundary[d][0] == kShrinkWrapMin) *min_lo[d] = std::min(*min_lo[d], lo[d] - margin[d]);
    if (domain->boundary[d][1] == kShrinkWrapMin) *min_hi[d] = std::max(*min_hi[d], hi[d] + margin[d]);
  }
  // LAMMPS's reset_box leaves the box of an empty system alone; LIGGGHTS's wraps it around the meshes
  // (and the minimum bounds), which the first insertion sees
  if (natoms > 0) return;
  for (int d = 0; d < 3; ++d) {
    if (domain->boundary[d][0] == kShrinkWrapMin) domain->boxlo[d] = *min_lo[d];
    if (domain->boundary[d][1] == kShrinkWrapMin) domain->boxhi[d] = *min_hi[d];
  }
  domain->set_global_box();
  domain->set_local_box();
}
}  // namespace dembridge
