#include "mesh_neighbors.h"

#include <algorithm>
#include <cmath>

namespace dembridge::mesh {

bool MeshNeighbors::in_reach(const TriangleMesh &m, int t, const Vec3 &p, double reach)
{
  // the triangle's bounding box grown by the reach (the LIGGGHTS edge-plane test alone admits
  // far points in the wedge beyond an acute corner; every real contact is inside the box)
  for (int d = 0; d < 3; ++d) {
    const double a = m.node(t, 0)[d], b = m.node(t, 1)[d], c = m.node(t, 2)[d];
    if (p[d] < std::min(a, std::min(b, c)) - reach || p[d] > std::max(a, std::max(b, c)) + reach) return false;
  }
  const Vec3 &n0 = m.node(t, 0);
  const double dplane = dot(sub(p, n0), m.normal(t));
  if (std::fabs(dplane) > reach) return false;
  for (int k = 0; k < 3; ++k) {
    const double de = dot(sub(p, m.node(t, k)), m.edge_norm(t, k));
    if (de > 0.0 && de * de > reach * reach) return false;
  }
  return true;
}

void MeshNeighbors::build_bins(const TriangleMesh &m, double reach)
{
  const int n = m.size();
  Vec3 lo = m.node(0, 0), hi = lo;
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], m.node(t, k)[d]);
        hi[d] = std::max(hi[d], m.node(t, k)[d]);
      }
  for (int d = 0; d < 3; ++d) {
    lo[d] -= reach;
    hi[d] += reach;
  }
  // Bins as small as the reach where affordable: a particle in the bulk, away from the walls,
  // then finds an empty bin and tests nothing. Target max(4 per triangle, 2^18) bins; never
  // smaller than the reach; grown until the grid is bounded.
  const double vol = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  const double target = std::max(4.0 * n, 262144.0);
  double h = std::max(reach, std::cbrt(vol / target));
  auto nbins = [&](double hh, int d) { return std::max(1, int(std::ceil((hi[d] - lo[d]) / hh))); };
  while (double(nbins(h, 0)) * nbins(h, 1) * nbins(h, 2) > 2.0 * target + 64.0) h *= 1.25;
  lo_ = lo;
  h_ = h;
  for (int d = 0; d < 3; ++d) nb_[d] = nbins(h, d);
  const long nbin = long(nb_[0]) * nb_[1] * nb_[2];

  // counting sort of (bin, triangle): triangle ids stay ascending inside each bin
  auto range = [&](int t, int d, int &b0, int &b1) {
    double a = m.node(t, 0)[d], b = a;
    for (int k = 1; k < 3; ++k) {
      a = std::min(a, m.node(t, k)[d]);
      b = std::max(b, m.node(t, k)[d]);
    }
    b0 = std::clamp(int(std::floor((a - reach - lo_[d]) / h_)), 0, nb_[d] - 1);
    b1 = std::clamp(int(std::floor((b + reach - lo_[d]) / h_)), 0, nb_[d] - 1);
  };
  // A bin of a triangle's grown box keeps it only if some point of the bin may pass in_reach: within
  // the reach of its plane and of no edge's outer side by more than the reach (the linear bounds of
  // the criterion over the bin's cube). The margin takes the rounding of these bounds, of in_reach
  // and of bin_of; a test that cannot pass is all a dropped entry removes, so the lists stay the same.
  double scale = 0.0;
  for (int d = 0; d < 3; ++d) scale = std::max(scale, std::max(std::fabs(lo[d]), std::fabs(hi[d])));
  const double half = 0.5 * h, limit = reach + 1e-6 * h + 1e-12 * scale;
  auto spread = [&](const Vec3 &u) { return half * (std::fabs(u[0]) + std::fabs(u[1]) + std::fabs(u[2])); };
  double sp[4] = {0.0, 0.0, 0.0, 0.0};  // of the plane and the three edges: how far their distances vary over a bin
  auto may_reach = [&](int t, int i, int j, int k) {
    const Vec3 c{lo_[0] + (i + 0.5) * h_, lo_[1] + (j + 0.5) * h_, lo_[2] + (k + 0.5) * h_};
    if (std::fabs(dot(sub(c, m.node(t, 0)), m.normal(t))) - sp[0] > limit) return false;
    for (int e = 0; e < 3; ++e)
      if (dot(sub(c, m.node(t, e)), m.edge_norm(t, e)) - sp[1 + e] > limit) return false;
    return true;
  };
  bin_first_.assign(nbin + 1, 0);
  std::vector<unsigned char> keep;  // may_reach of each bin entry, in the order of the first pass
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill;
    if (pass == 1) {
      for (long b = 0; b < nbin; ++b) bin_first_[b + 1] += bin_first_[b];
      bin_tri_.assign(bin_first_[nbin], 0);
      fill.assign(bin_first_.begin(), bin_first_.end() - 1);
    }
    std::size_t entry = 0;
    for (int t = 0; t < n; ++t) {
      int r0[3], r1[3];
      for (int d = 0; d < 3; ++d) range(t, d, r0[d], r1[d]);
      if (pass == 0) {
        sp[0] = spread(m.normal(t));
        for (int e = 0; e < 3; ++e) sp[1 + e] = spread(m.edge_norm(t, e));
      }
      for (int i = r0[0]; i <= r1[0]; ++i)
        for (int j = r0[1]; j <= r1[1]; ++j)
          for (int k = r0[2]; k <= r1[2]; ++k, ++entry) {
            if (pass == 0) keep.push_back(may_reach(t, i, j, k));
            if (!keep[entry]) continue;
            const long b = (long(i) * nb_[1] + j) * nb_[2] + k;
            if (pass == 0) ++bin_first_[b + 1];
            else bin_tri_[fill[b]++] = t;
          }
    }
  }
}

long MeshNeighbors::bin_of(const Vec3 &p) const
{
  int c[3];
  for (int d = 0; d < 3; ++d) {
    const double f = (p[d] - lo_[d]) / h_;  // int(f) is floor(f) once f >= 0 (no floor call per particle)
    if (!(f >= 0.0) || f >= nb_[d]) return -1;
    c[d] = int(f);
  }
  return (long(c[0]) * nb_[1] + c[1]) * nb_[2] + c[2];
}

void MeshNeighbors::build(const TriangleMesh &m, int n, const double *const *x, const double *radius,
                          const int *skip, double s)
{
  first_.assign(n + 1, 0);
  tri_.clear();
  tests_ = 0;
  ++builds_;
  if (m.size() == 0) return;  // a rank of a distributed mesh may keep no triangle
  double rmax = 0.0;
  for (int i = 0; i < n; ++i)
    if (!skip || !skip[i]) rmax = std::max(rmax, radius[i]);
  if (&m != binned_mesh_ || m.geometry_version() != binned_version_ || rmax + s != binned_reach_) {
    build_bins(m, rmax + s);
    binned_mesh_ = &m;
    binned_version_ = m.geometry_version();
    binned_reach_ = rmax + s;
  }
  for (int i = 0; i < n; ++i) {
    first_[i] = static_cast<int>(tri_.size());
    if (skip && skip[i]) continue;
    const Vec3 p{x[i][0], x[i][1], x[i][2]};
    const long b = bin_of(p);
    if (b < 0) continue;
    const double reach = radius[i] + s;
    tests_ += std::size_t(bin_first_[b + 1] - bin_first_[b]);
    for (int q = bin_first_[b]; q < bin_first_[b + 1]; ++q)
      if (in_reach(m, bin_tri_[q], p, reach)) tri_.push_back(bin_tri_[q]);
  }
  first_[n] = static_cast<int>(tri_.size());
}

double MeshNeighbors::memory_bytes() const
{
  return double(first_.capacity() + tri_.capacity() + bin_first_.capacity() + bin_tri_.capacity()) * sizeof(int);
}

}  // namespace dembridge::mesh
