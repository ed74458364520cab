#pragma once
// LIGGGHTS shrink-wraps the box around the nodes of its mesh fixes as well as the atoms (its reset_box
// asks every fix for its extent), at every re-neighbouring, so a moving mesh carries the box along.
// LAMMPS's reset_box wraps the atoms only; but for a face 'm' it keeps the face at or beyond a
// minimum bound. So, around each re-neighbouring's reset_box, every shrink-wrapped face ('s' or 'm')
// becomes an 'm' face whose minimum also reaches the meshes' nodes plus the wrap margin; afterwards
// the faces and minima are the user's again. min() commutes with the rounded +-margin (rounding is
// monotone), so the box is LIGGGHTS's bit for bit.
#include "triangle_mesh.h"

namespace LAMMPS_NS {
class Domain;
}

namespace dembridge {

// The extent (node bounding box) of one mesh, for the union over the mesh fixes.
struct MeshExtent {
  mesh::Vec3 lo{}, hi{};
  bool empty = true;
  void add(const mesh::Vec3 &l, const mesh::Vec3 &h);
};
MeshExtent node_extent(const mesh::TriangleMesh &m);

class ShrinkWrapAroundMeshes {
 public:
  // Before reset_box (pre_exchange): the faces become 'm' with minima widened to `e`. A system
  // without atoms (natoms 0), whose box LAMMPS's reset_box leaves alone, gets LIGGGHTS's box here.
  void open(LAMMPS_NS::Domain *domain, const MeshExtent &e, long long natoms);
  // After it (pre_neighbor, post_run): the user's faces and minima again. Does nothing if not open.
  void close(LAMMPS_NS::Domain *domain);
  // Only the box of an empty system (as open() sets it), nothing left changed: for init().
  static void set_empty_box(LAMMPS_NS::Domain *domain, const MeshExtent &e);

 private:
  bool open_ = false;
  int boundary_[3][2] = {{0, 0}, {0, 0}, {0, 0}};
  double min_[3][2] = {{0, 0}, {0, 0}, {0, 0}};
};

}  // namespace dembridge
