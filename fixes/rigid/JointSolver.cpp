#include "JointSolver.h"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <Eigen/SparseQR>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace dembridge::rigid {

namespace {
Mat3 skew(const Vec3 &a)
{
  Mat3 m;
  m << 0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0;
  return m;
}

int find(std::vector<int> &parent, int i)
{
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}
}  // namespace

Mat3 JointClusters::point_operator(const Mat3 &L, const Vec3 &arm) { return -L * skew(arm); }

JointClusters::JointClusters(int nbodies, std::vector<JointDef> joints) : joints_(std::move(joints))
{
  std::vector<int> parent(nbodies);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t j = 0; j < joints_.size(); j++) {
    const JointDef &d = joints_[j];
    if (d.body1 < 0 || d.body1 >= nbodies || d.body2 < -1 || d.body2 >= nbodies)
      throw std::invalid_argument("joint " + std::to_string(j) + ": body index out of range");
    if (d.body1 == d.body2) throw std::invalid_argument("joint " + std::to_string(j) + " joins a body with itself");
    if (d.body2 >= 0) parent[find(parent, d.body1)] = find(parent, d.body2);
  }
  std::map<int, int> which;  // root -> cluster, clusters ordered by their first joint
  for (std::size_t j = 0; j < joints_.size(); j++) {
    const int r = find(parent, joints_[j].body1);
    auto it = which.find(r);
    if (it == which.end()) {
      it = which.emplace(r, int(clusters_.size())).first;
      clusters_.emplace_back();
    }
    clusters_[it->second].push_back(int(j));
  }
  checked_.assign(clusters_.size(), 0);
  lu_.resize(clusters_.size());
}

JointClusters::~JointClusters() = default;

std::vector<Vec3> JointClusters::solve(const std::vector<BodyKinematics> &B, double h, bool q16) const
{
  std::vector<Vec3> R(joints_.size(), Vec3::Zero());
  for (const auto &cl : clusters_) {
    const int n = int(cl.size());
    // (body, joint row, sign, H) of every joint end in this cluster
    struct End {
      int body, row;
      double sign;
      Mat3 H;
    };
    std::vector<End> ends;
    Eigen::VectorXd rhs(3 * n);
    for (int k = 0; k < n; k++) {
      const JointDef &d = joints_[cl[k]];
      Vec3 now = Vec3::Zero(), free = Vec3::Zero();
      for (int e = 0; e < 2; e++) {
        const int b = e == 0 ? d.body1 : d.body2;
        if (b < 0) continue;
        const double s = e == 0 ? 1.0 : -1.0;
        const Mat3 H = point_operator(B[b].L, e == 0 ? d.arm1 : d.arm2);
        now += s * (B[b].v + H * B[b].W);
        free += s * (B[b].v_free + H * B[b].W_free);
        ends.push_back({b, k, s, H});
      }
      rhs.segment<3>(3 * k) = -(now + free);
    }
    // blocks couple the joint ends that share a body: group the ends by body (O(ends), not O(ends²))
    std::map<int, std::vector<int>> by_body;
    for (std::size_t e = 0; e < ends.size(); e++) by_body[ends[e].body].push_back(int(e));
    std::vector<Eigen::Triplet<double>> trip;
    for (const auto &bb : by_body)
      for (int ia : bb.second)
        for (int ic : bb.second) {
          const End &a = ends[ia], &c = ends[ic];
          const BodyKinematics &b = B[a.body];
          const Mat3 blk = a.sign * c.sign *
                           (b.inv_mass * Mat3::Identity() +
                            (q16 && a.row != c.row ? Mat3(c.H * b.inv_inertia * a.H.transpose())
                                                   : Mat3(a.H * b.inv_inertia * c.H.transpose())));
          for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++)
              trip.emplace_back(3 * a.row + r, 3 * c.row + s, blk(r, s));  // zeros too: the pattern stays fixed
        }
    Eigen::SparseMatrix<double> W(3 * n, 3 * n);
    W.setFromTriplets(trip.begin(), trip.end());
    W.makeCompressed();
    const int ci = int(&cl - clusters_.data());
    if (!checked_[ci]) {
      // a redundant constraint (e.g. a body pinned twice at one point) makes W rank deficient: LU may
      // still find round-off pivots, so the rank is checked once per cluster (the structure is fixed)
      Eigen::SparseQR<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> qr;
      double dmax = 0.0;
      for (int r = 0; r < 3 * n; r++) dmax = std::max(dmax, std::abs(W.coeff(r, r)));
      qr.setPivotThreshold(1e-10 * dmax);
      qr.compute(W);
      if (qr.info() != Eigen::Success || qr.rank() < 3 * n) throw SingularCluster("singular joint cluster", cl);
      checked_[ci] = 1;
    }
    // the sparsity pattern of a cluster never changes: analyse it once, factorize every step
    if (!lu_[ci]) {
      lu_[ci] = std::make_unique<Eigen::SparseLU<Eigen::SparseMatrix<double>>>();
      lu_[ci]->analyzePattern(W);
    }
    auto &lu = *lu_[ci];
    lu.factorize(W);
    if (lu.info() != Eigen::Success) throw SingularCluster("singular joint cluster", cl);
    const Eigen::VectorXd x = lu.solve(rhs);
    if (lu.info() != Eigen::Success || !x.allFinite()) throw SingularCluster("singular joint cluster", cl);
    for (int k = 0; k < n; k++) R[cl[k]] = x.segment<3>(3 * k) / h;
  }
  return R;
}

}  // namespace dembridge::rigid
