#include "mesh_box_extent.h"

#include "domain.h"

#include <algorithm>

namespace dembridge {
namespace {
constexpr int kShrinkWrap = 2;     // Domain::boundary code of 's'
constexpr int kShrinkWrapMin = 3;  // of 'm'

// Domain::small (the wrap margin, 1e-4 of the initial box) is protected; a derived class may name it.
struct DomainMargin : LAMMPS_NS::Domain {
  static const double *of(const LAMMPS_NS::Domain *d) { return d->*(&DomainMargin::small); }
};

bool shrink_wrapped(const LAMMPS_NS::Domain *d, int dim, int side)
{
  return d->boundary[dim][side] == kShrinkWrap || d->boundary[dim][side] == kShrinkWrapMin;
}

double *min_bound(LAMMPS_NS::Domain *d, int dim, int side)
{
  double *lo[3] = {&d->minxlo, &d->minylo, &d->minzlo};
  double *hi[3] = {&d->minxhi, &d->minyhi, &d->minzhi};
  return side == 0 ? lo[dim] : hi[dim];
}

// LIGGGHTS's face with only the meshes (no atoms): node extent -+ margin; an 'm' face also its minimum.
double mesh_face(const LAMMPS_NS::Domain *d, const MeshExtent &e, int dim, int side, double user_min)
{
  const double *margin = DomainMargin::of(d);
  double face = side == 0 ? e.lo[dim] - margin[dim] : e.hi[dim] + margin[dim];
  if (d->boundary[dim][side] == kShrinkWrapMin) face = side == 0 ? std::min(face, user_min) : std::max(face, user_min);
  return face;
}

bool applies(const LAMMPS_NS::Domain *d, const MeshExtent &e) { return d->nonperiodic == 2 && !d->triclinic && !e.empty; }
}  // namespace

void MeshExtent::add(const mesh::Vec3 &l, const mesh::Vec3 &h)
{
  for (int d = 0; d < 3; ++d) {
    lo[d] = empty ? l[d] : std::min(lo[d], l[d]);
    hi[d] = empty ? h[d] : std::max(hi[d], h[d]);
  }
  empty = false;
}

MeshExtent node_extent(const mesh::TriangleMesh &m)
{
  MeshExtent e;
  for (int t = 0; t < m.size(); ++t)
    for (int k = 0; k < 3; ++k) e.add(m.node(t, k), m.node(t, k));
  return e;
}

void ShrinkWrapAroundMeshes::open(LAMMPS_NS::Domain *domain, const MeshExtent &e, long long natoms)
{
  close(domain);
  if (!applies(domain, e)) return;
  if (natoms == 0) set_empty_box(domain, e);
  for (int d = 0; d < 3; ++d)
    for (int s = 0; s < 2; ++s) {
      boundary_[d][s] = domain->boundary[d][s];
      min_[d][s] = *min_bound(domain, d, s);
      if (!shrink_wrapped(domain, d, s)) continue;
      *min_bound(domain, d, s) = mesh_face(domain, e, d, s, min_[d][s]);
      domain->boundary[d][s] = kShrinkWrapMin;
    }
  open_ = true;
}

void ShrinkWrapAroundMeshes::close(LAMMPS_NS::Domain *domain)
{
  if (!open_) return;
  for (int d = 0; d < 3; ++d)
    for (int s = 0; s < 2; ++s) {
      domain->boundary[d][s] = boundary_[d][s];
      *min_bound(domain, d, s) = min_[d][s];
    }
  open_ = false;
}

void ShrinkWrapAroundMeshes::set_empty_box(LAMMPS_NS::Domain *domain, const MeshExtent &e)
{
  if (!applies(domain, e)) return;
  for (int d = 0; d < 3; ++d) {
    if (shrink_wrapped(domain, d, 0)) domain->boxlo[d] = mesh_face(domain, e, d, 0, *min_bound(domain, d, 0));
    if (shrink_wrapped(domain, d, 1)) domain->boxhi[d] = mesh_face(domain, e, d, 1, *min_bound(domain, d, 1));
  }
  domain->set_global_box();
  domain->set_local_box();
}

}  // namespace dembridge
