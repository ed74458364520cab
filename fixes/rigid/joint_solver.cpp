#include "joint_solver.h"
#include "skyline_lu.h"

#include <Eigen/Sparse>
#include <Eigen/SparseQR>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <set>

namespace dembridge::rigid {

namespace {
Mat3 skew(const Vec3 &a)
{
  Mat3 m;
  m << 0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0;
  return m;
}
}  // namespace

// H = Λ [X − P]× as joints.cpp forms it (NNMUL), with the body-frame arm b = P − X
Mat3 JointClusters::point_operator(const Mat3 &L, const Vec3 &arm) { return macro_mul(L, skew(-arm)); }

JointClusters::JointClusters(int nbodies, std::vector<JointDef> joints) : joints_(std::move(joints))
{
  const int nj = int(joints_.size());
  std::vector<std::set<int>> by_body(nbodies);
  for (int j = 0; j < nj; j++) {
    const JointDef &d = joints_[j];
    if (d.body1 < 0 || d.body1 >= nbodies || d.body2 < -1 || d.body2 >= nbodies)
      throw std::invalid_argument("joint " + std::to_string(j) + ": body index out of range");
    if (d.body1 == d.body2) throw std::invalid_argument("joint " + std::to_string(j) + " joins a body with itself");
    by_body[d.body1].insert(j);
    if (d.body2 >= 0) by_body[d.body2].insert(j);
  }
  // joint adjacency (joints sharing a body), then Parmec's clusters: depth-first from the lowest unvisited
  // joint, neighbours in increasing order; the order fixes the unknowns' order and so the LU's round-off
  std::vector<std::set<int>> adj(nj);
  for (const auto &b : by_body)
    for (int a : b)
      for (int c : b)
        if (a != c) adj[a].insert(c);
  std::vector<char> seen(nj, 0);
  for (int start = 0; start < nj; start++) {
    if (seen[start]) continue;
    clusters_.emplace_back();
    std::vector<int> &cl = clusters_.back();
    std::function<void(int)> visit = [&](int j) {
      if (seen[j]) return;
      seen[j] = 1;
      cl.push_back(j);
      for (int k : adj[j]) visit(k);
    };
    visit(start);
  }
  checked_.assign(clusters_.size(), 0);
}

JointClusters::~JointClusters() = default;

std::vector<Vec3> JointClusters::solve(const std::vector<BodyKinematics> &B, double h, bool q16) const
{
  std::vector<Vec3> R(joints_.size(), Vec3::Zero());
  for (std::size_t ci = 0; ci < clusters_.size(); ci++) {
    const std::vector<int> &cl = clusters_[ci];
    const int n = int(cl.size());
    std::map<int, int> row_of;  // joint -> position in the cluster
    for (int k = 0; k < n; k++) row_of[cl[k]] = k;
    std::map<int, std::vector<int>> joints_of;  // body -> its joints, increasing
    for (int j : cl)
      for (int b : {joints_[j].body1, joints_[j].body2})
        if (b >= 0) joints_of[b].push_back(j);
    for (auto &jb : joints_of) std::sort(jb.second.begin(), jb.second.end());

    // W blocks as joints.cpp forms them: W_ii = Σ_parts (H J⁻¹ Hᵀ + I/m), W_ij = ±(H_i J⁻¹ H_jᵀ + I/m),
    // each stored transposed (Parmec's column-major block into a row-major system); off-diagonal blocks
    // untransposed unless q16
    SkylineLU lu(3 * n);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(3 * n);
    auto put = [&](int r0, int c0, const Mat3 &W, bool transpose) {
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) lu.add(3 * r0 + a, 3 * c0 + b, transpose ? W(b, a) : W(a, b));
    };
    for (int i0 = 0; i0 < n; i0++) {
      const int i = cl[i0];
      const JointDef &d = joints_[i];
      Mat3 Wii = Mat3::Zero();
      Vec3 Bi = Vec3::Zero();
      for (int e = 0; e < 2; e++) {
        const int b = e == 0 ? d.body1 : d.body2;
        if (b < 0) continue;
        const BodyKinematics &K = B[b];
        const Mat3 Hi = point_operator(K.L, e == 0 ? d.arm1 : d.arm2);
        const Mat3 C = macro_mul_t(K.inv_inertia, Hi);
        const Mat3 D = macro_mul(Hi, C);
        Wii = Wii + D;
        for (int a = 0; a < 3; a++) Wii(a, a) += K.inv_mass;
        for (int j : joints_of[b]) {
          if (j == i) continue;
          const JointDef &dj = joints_[j];
          const Mat3 Hj = point_operator(K.L, dj.body1 == b ? dj.arm1 : dj.arm2);
          const Mat3 Cj = macro_mul_t(K.inv_inertia, Hj);
          Mat3 Wij = macro_mul(Hi, Cj);
          for (int a = 0; a < 3; a++) Wij(a, a) += K.inv_mass;
          if ((b == d.body1 && b == dj.body2) || (b == d.body2 && b == dj.body1)) Wij = -Wij;
          put(i0, row_of[j], Wij, q16);
        }
        // right-hand side −(U_rel(t_n) + U_rel,free(t_n+1)), part 1 subtracted, part 2 added
        const Vec3 V = macro_mv(Hi, K.W) + K.v;
        const Vec3 Cf = (macro_mv(Hi, K.W_free) + K.v_free) + K.kick;
        if (e == 0)
          Bi = Bi - (V + Cf);
        else
          Bi = Bi + (V + Cf);
      }
      put(i0, i0, Wii, true);
      rhs.segment<3>(3 * i0) = Bi;
    }

    if (!checked_[ci]) {
      // a redundant constraint (e.g. a body pinned twice at one point) makes W rank deficient: LU may
      // still find round-off pivots, so the rank is checked once per cluster (the structure is fixed)
      Eigen::SparseMatrix<double> W = lu.sparse();
      Eigen::SparseQR<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> qr;
      double dmax = 0.0;
      for (int r = 0; r < 3 * n; r++) dmax = std::max(dmax, std::abs(W.coeff(r, r)));
      qr.setPivotThreshold(1e-10 * dmax);
      qr.compute(W);
      if (qr.info() != Eigen::Success || qr.rank() < 3 * n) throw SingularCluster("singular joint cluster", cl);
      checked_[ci] = 1;
    }
    std::vector<double> x(rhs.data(), rhs.data() + 3 * n);
    if (!lu.factorize() || !lu.solve(x)) throw SingularCluster("singular joint cluster", cl);
    const double inv_h = 1.0 / h;  // Parmec scales the impulses by 1/h
    for (int k = 0; k < n; k++) {
      const Vec3 r(x[3 * k] * inv_h, x[3 * k + 1] * inv_h, x[3 * k + 2] * inv_h);
      if (!r.allFinite()) throw SingularCluster("singular joint cluster", cl);
      R[cl[k]] = r;
    }
  }
  return R;
}

}  // namespace dembridge::rigid
