// Binned particle-triangle candidate search (spec liggghts-walls §6).
// Triangles are sorted into a uniform grid of bins over the mesh bounding box grown by the
// largest particle reach; each particle then tests only the triangles of its own bin with the
// LIGGGHTS list criterion. Cost per rebuild: O(triangles + particles x triangles-per-bin); the
// candidate lists are per particle, with triangle ids ascending (= LIGGGHTS's force order).
#pragma once

#include "triangle_mesh.h"

#include <cstdint>
#include <vector>

namespace dembridge::mesh {

class MeshNeighbors {
 public:
  // n particles (x[i] = centre, radius[i]); skip[i] != 0 excludes a particle (may be null).
  // The bins are rebuilt only if the mesh moved or the largest reach changed.
  // s = the extra reach: skin/2 for a static mesh, skin for a moving one (spec §6).
  void build(const TriangleMesh &mesh, int n, const double *const *x, const double *radius,
             const int *skip, double s);

  int count(int i) const { return first_[i + 1] - first_[i]; }
  const int *begin(int i) const { return tri_.data() + first_[i]; }
  int nparticles() const { return static_cast<int>(first_.size()) - 1; }
  std::size_t total() const { return tri_.size(); }
  std::size_t tests_performed() const { return tests_; }  // criterion evaluations of the last build
  std::uint64_t builds() const { return builds_; }  // how often the lists were built (they change only then)
  double memory_bytes() const;

  // The §6 criterion for one particle and triangle, and inside the triangle's bounding box grown
  // by the reach. A superset of every contact within the reach.
  static bool in_reach(const TriangleMesh &mesh, int t, const Vec3 &p, double reach);

 private:
  std::vector<int> first_{0};
  std::vector<int> tri_;
  std::size_t tests_ = 0;
  std::uint64_t builds_ = 0;
  // bins
  Vec3 lo_{};
  double h_ = 1.0;
  int nb_[3] = {1, 1, 1};
  std::vector<int> bin_first_, bin_tri_;
  // the bins are kept while the mesh has not moved and the reach is the same (static meshes:
  // built once)
  const TriangleMesh *binned_mesh_ = nullptr;
  std::uint64_t binned_version_ = 0;
  double binned_reach_ = -1.0;
  void build_bins(const TriangleMesh &mesh, double reach);
  long bin_of(const Vec3 &p) const;
};

}  // namespace dembridge::mesh
