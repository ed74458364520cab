#pragma once
// LIGGGHTS shrink-wraps the box around the nodes of its mesh fixes as well as the atoms; for 'm'
// boundaries LAMMPS does the same if its minimum box bounds include the nodes (minus the wrap margin).
#include "triangle_mesh.h"

namespace LAMMPS_NS {
class Domain;
}

namespace dembridge {
// Lowers/raises domain->min{x,y,z}{lo,hi} of each orthogonal 'm' face to the mesh's extent, so that
// Domain::reset_box gives LIGGGHTS's box; with no atoms (natoms 0) sets those faces of the box too.
// 's' faces are left alone (LAMMPS has no hook for them).
void widen_shrink_wrap_minimum(LAMMPS_NS::Domain *domain, const mesh::TriangleMesh &m, long long natoms);
}  // namespace dembridge
