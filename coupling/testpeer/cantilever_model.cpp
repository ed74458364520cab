#include "cantilever_model.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "free_bodies_model.h"  // cayley_rotation

namespace dembridge::mbdyn::testpeer {

namespace {

using Block = std::array<std::array<double, 3>, 3>;

V3 add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 scale(const V3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
V3 mul_t(const Mat3& R, const V3& v) { return rotate_vector(transpose(R), v); }
Mat3 skew(const V3& v) { return Mat3{{{0, -v[2], v[1]}, {v[2], 0, -v[0]}, {-v[1], v[0], 0}}}; }
Mat3 eye() { return Mat3{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }
Mat3 scaled(const Mat3& A, double s) {
  Mat3 B = A;
  for (auto& r : B)
    for (double& x : r) x *= s;
  return B;
}
Mat3 plus(const Mat3& A, const Mat3& B) {
  Mat3 C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C[i][j] = A[i][j] + B[i][j];
  return C;
}
Mat3 minus(const Mat3& A, const Mat3& B) { return plus(A, scaled(B, -1.0)); }
// MBDyn's Mat3x3(CGR_Rot::MatG, g): w = G(g) g'
Mat3 cayley_g_matrix(const V3& g) {
  const double d = 4.0 / (4.0 + g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  const double a = 0.5 * g[0] * d, b = 0.5 * g[1] * d, c = 0.5 * g[2] * d;
  return Mat3{{{d, -c, b}, {c, d, -a}, {-b, a, d}}};
}
// MBDyn's RotManip::VecRot for the clamp's (tiny) orientation error
V3 rotation_vector(const Mat3& R) {
  const V3 a{0.5 * (R[2][1] - R[1][2]), 0.5 * (R[0][2] - R[2][0]), 0.5 * (R[1][0] - R[0][1])};
  const double s = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (s < 1e-8) return a;
  const double c = 0.5 * (R[0][0] + R[1][1] + R[2][2] - 1.0);
  return scale(a, std::atan2(s, c) / s);
}

// beam2's shape functions at its mid-point (xi = 0) and their derivatives
constexpr double kN[2] = {0.5, 0.5};
constexpr double kNP[2] = {-0.5, 0.5};

}  // namespace

CantileverModel::CantileverModel(const CantileverSpec& spec) : spec_(spec) {
  const std::size_t N = spec.node_x.size();
  if (N < 2) throw std::runtime_error("cantilever: needs at least two nodes");
  nodes_.resize(N);
  for (std::size_t k = 0; k < N; ++k) {
    Node& n = nodes_[k];
    n.dynamic = k > 0;
    n.base = k == 0 ? 0 : 6 + 12 * static_cast<int>(k - 1);
    n.x = spec.node_x[k];
    n.R = n.RRef = n.RPrev = eye();
  }
  clamp_ = 6 + 12 * static_cast<int>(N - 1);
  n_ = clamp_ + 6;
  X_.assign(n_, 0.0);
  XP_.assign(n_, 0.0);
  algebraic_.assign(n_, false);
  for (int i = 0; i < 6; ++i) algebraic_[clamp_ + i] = true;
  for (const Node& n : nodes_)  // SetValue: x, g = 0, v, w (the bodies' momenta m v, J w are 0 at rest)
    for (int i = 0; i < 3; ++i) {
      X_[n.base + i] = n.x[i];
      XP_[n.base + i] = n.v[i];
      XP_[n.base + 3 + i] = n.w[i];
    }
  for (std::size_t k = 0; k + 1 < N; ++k) {
    Beam e;
    e.a = static_cast<int>(k);
    e.b = static_cast<int>(k + 1);
    e.R = e.RRef = e.RPrev = eye();
    const V3& xa = nodes_[k].x;
    const V3& xb = nodes_[k + 1].x;
    const V3 grad = add(scale(xa, kNP[0]), scale(xb, kNP[1]));
    const double d = grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2];
    e.dsdxi = 1.0 / std::sqrt(d);
    e.L0 = mul_t(e.R, scale(grad, e.dsdxi));
    e.p = add(scale(xa, kN[0]), scale(xb, kN[1]));
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) e.DRef[r][c] = r == c ? spec.stiffness[r] : 0.0;
    beams_.push_back(e);
  }
}

std::vector<CantileverNode> CantileverModel::nodes() const {
  std::vector<CantileverNode> out(nodes_.size());
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    out[k].x = nodes_[k].x;
    out[k].v = nodes_[k].v;
    out[k].w = nodes_[k].w;
    out[k].R = nodes_[k].R;
  }
  return out;
}

void CantileverModel::nodes_from_state() {
  for (Node& n : nodes_) {
    for (int i = 0; i < 3; ++i) {
      n.x[i] = X_[n.base + i];
      n.v[i] = XP_[n.base + i];
      n.g[i] = X_[n.base + 3 + i];
      n.gp[i] = XP_[n.base + 3 + i];
    }
    const Mat3 Rd = cayley_rotation(n.g);
    n.R = multiply(Rd, n.RRef);
    n.w = add(rotate_vector(cayley_g_matrix(n.g), n.gp), rotate_vector(Rd, n.WRef));
  }
}

// The section's actions from its strain at the mid-point: R = Rd(mean g) RRef, strain R^T x' - L0,
// curvature R^T G(g) g' added to the reference curvature of the step.
void CantileverModel::beam_residual_update(Beam& e) {
  const Node& A = nodes_[e.a];
  const Node& B = nodes_[e.b];
  e.p = add(scale(A.x, kN[0]), scale(B.x, kN[1]));
  const V3 g = add(scale(A.g, kN[0]), scale(B.g, kN[1]));
  e.R = multiply(cayley_rotation(g), e.RRef);
  e.L = scale(add(scale(A.x, kNP[0]), scale(B.x, kNP[1])), e.dsdxi);
  const V3 ggrad = scale(add(scale(A.g, kNP[0]), scale(B.g, kNP[1])), e.dsdxi);
  e.eps = sub(mul_t(e.R, e.L), e.L0);
  e.kappa = add(mul_t(e.R, rotate_vector(cayley_g_matrix(g), ggrad)), e.kappa_ref);
  V3 f, m;
  for (int i = 0; i < 3; ++i) {
    f[i] = spec_.stiffness[i] * e.eps[i];
    m[i] = spec_.stiffness[3 + i] * e.kappa[i];
  }
  e.F = rotate_vector(e.R, f);
  e.M = rotate_vector(e.R, m);
}

// After the predictor: the reference orientation of the step from the nodes' predicted increments.
void CantileverModel::beam_after_predict(Beam& e) {
  const Node& A = nodes_[e.a];
  const Node& B = nodes_[e.b];
  e.p = add(scale(A.x, kN[0]), scale(B.x, kN[1]));
  const V3 g = add(scale(A.gRef, kN[0]), scale(B.gRef, kN[1]));
  e.R = e.RRef = multiply(cayley_rotation(g), e.RPrev);
  e.L = scale(add(scale(A.x, kNP[0]), scale(B.x, kNP[1])), e.dsdxi);
  const V3 ggrad = scale(add(scale(A.gRef, kNP[0]), scale(B.gRef, kNP[1])), e.dsdxi);
  e.eps = sub(mul_t(e.R, e.L), e.L0);
  e.kappa = e.kappa_ref = add(mul_t(e.R, rotate_vector(cayley_g_matrix(g), ggrad)), e.kappa_prev);
  V3 f, m;
  for (int i = 0; i < 3; ++i) {
    f[i] = spec_.stiffness[i] * e.eps[i];
    m[i] = spec_.stiffness[3 + i] * e.kappa[i];
  }
  e.F = rotate_vector(e.R, f);
  e.M = rotate_vector(e.R, m);
  // R D R^T per 3 x 3 block (the law is diagonal: the off-diagonal blocks stay 0)
  for (int blk = 0; blk < 2; ++blk) {
    Mat3 D{};
    for (int i = 0; i < 3; ++i) D[i][i] = spec_.stiffness[3 * blk + i];
    const Mat3 RD = multiply(e.R, multiply(D, transpose(e.R)));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) e.DRef[3 * blk + i][3 * blk + j] = RD[i][j];
  }
}

std::vector<double> CantileverModel::residual(const NodalLoads& loads, double dcoef, bool update_beams) {
  std::vector<double> f(n_, 0.0);
  auto addv = [&](int row, const V3& v, double s) {
    for (int i = 0; i < 3; ++i) f[row + i] += s * v[i];
  };
  for (const Node& n : nodes_) {
    if (!n.dynamic) continue;
    const int b = n.base, mr = b + 6;
    const V3 B{X_[b + 6], X_[b + 7], X_[b + 8]}, G{X_[b + 9], X_[b + 10], X_[b + 11]};
    const V3 BP{XP_[b + 6], XP_[b + 7], XP_[b + 8]}, GP{XP_[b + 9], XP_[b + 10], XP_[b + 11]};
    // automatic structural element: B, G definitions, B' = F, G' + v x B = M
    addv(b, B, 1);
    addv(b + 3, G, 1);
    addv(mr, BP, -1);
    addv(mr + 3, add(GP, cross(n.v, B)), -1);
    // body: B - m v, G - J w; its weight
    const Mat3 J = multiply(n.R, multiply(scaled(eye(), spec_.inertia), transpose(n.R)));
    addv(b, scale(n.v, spec_.mass), -1);
    addv(b + 3, rotate_vector(J, n.w), -1);
    addv(mr, scale(spec_.gravity, spec_.mass), 1);
  }
  for (Beam& e : beams_) {
    if (update_beams) beam_residual_update(e);
    const Node& A = nodes_[e.a];
    const Node& B = nodes_[e.b];
    addv(mom_row(A), e.F, 1);
    addv(mom_row(A) + 3, add(cross(sub(e.p, A.x), e.F), e.M), 1);
    addv(mom_row(B), e.F, -1);
    addv(mom_row(B) + 3, add(e.M, cross(sub(e.p, B.x), e.F)), -1);
  }
  {  // clamp of node 0 at its initial pose
    const Node& n = nodes_[0];
    const V3 F{X_[clamp_], X_[clamp_ + 1], X_[clamp_ + 2]}, M{X_[clamp_ + 3], X_[clamp_ + 4], X_[clamp_ + 5]};
    addv(mom_row(n), F, -1);
    addv(mom_row(n) + 3, M, -1);
    if (dcoef != 0) {
      addv(clamp_, scale(sub(n.x, spec_.node_x[0]), 1.0 / dcoef), -1);
      addv(clamp_ + 3, scale(rotation_vector(n.R), 1.0 / dcoef), -1);
    }
  }
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    addv(mom_row(nodes_[k]), loads.force[k], 1);
    addv(mom_row(nodes_[k]) + 3, loads.moment[k], 1);
  }
  return f;
}

std::vector<double> CantileverModel::jacobian(double dcoef) const {
  std::vector<double> J(static_cast<std::size_t>(n_) * n_, 0.0);
  auto at = [&](int r, int c) -> double& { return J[static_cast<std::size_t>(r) * n_ + c]; };
  auto addb = [&](int r, int c, const Mat3& M, double s) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) at(r + i, c + j) += s * M[i][j];
  };
  for (const Node& n : nodes_) {
    if (!n.dynamic) continue;
    const int b = n.base, mr = b + 6;
    const V3 B{X_[b + 6], X_[b + 7], X_[b + 8]};
    for (int i = 0; i < 6; ++i) {
      at(b + i, b + 6 + i) += -dcoef;
      at(mr + i, b + 6 + i) += 1.0;
    }
    addb(mr + 3, b + 6, skew(scale(n.v, dcoef)), 1);
    addb(mr + 3, b, skew(B), -1);
    const Mat3 Jb = multiply(n.R, multiply(scaled(eye(), spec_.inertia), transpose(n.R)));
    addb(b, b, scaled(eye(), spec_.mass), 1);
    addb(b + 3, b + 3, Jb, 1);
    addb(b + 3, b + 3, skew(rotate_vector(Jb, scale(n.w, dcoef))), -1);
  }
  for (const Beam& e : beams_) {
    const Node* nd[2] = {&nodes_[e.a], &nodes_[e.b]};
    const int ra = mom_row(*nd[0]), rb = mom_row(*nd[1]);
    const V3 ba = sub(e.p, nd[0]->x), bb = sub(e.p, nd[1]->x);
    Mat3 D[2][2];
    for (int I = 0; I < 2; ++I)
      for (int K = 0; K < 2; ++K)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) D[I][K][i][j] = e.DRef[3 * I + i][3 * K + j];
    for (int i = 0; i < 2; ++i) {
      const double c = kNP[i] * e.dsdxi * dcoef;
      const Mat3 A11 = scaled(eye(), c), A12 = skew(scale(e.L, kN[i] * dcoef)), A22 = scaled(eye(), c);
      // D (strain, curvature <- x, g) with the rotation of the actions to global
      const Mat3 T11 = multiply(D[0][0], A11);
      const Mat3 T12 = minus(plus(multiply(D[0][0], A12), multiply(D[0][1], A22)), skew(scale(e.F, kN[i] * dcoef)));
      const Mat3 T21 = multiply(D[1][0], A11);
      const Mat3 T22 = minus(plus(multiply(D[1][0], A12), multiply(D[1][1], A22)), skew(scale(e.M, kN[i] * dcoef)));
      const int cx = nd[i]->base, cg = nd[i]->base + 3;
      const Mat3 Fx = skew(scale(e.F, dcoef * kN[i]));
      addb(ra, cx, T11, -1);
      addb(ra, cg, T12, -1);
      addb(ra + 3, cx, plus(minus(T21, Fx), multiply(skew(ba), T11)), -1);
      addb(ra + 3, cg, plus(T22, multiply(skew(ba), T12)), -1);
      addb(rb, cx, T11, 1);
      addb(rb, cg, T12, 1);
      addb(rb + 3, cx, plus(minus(T21, Fx), multiply(skew(bb), T11)), 1);
      addb(rb + 3, cg, plus(T22, multiply(skew(bb), T12)), 1);
    }
    const Mat3 Ft = skew(scale(e.F, dcoef));
    addb(ra + 3, nd[0]->base, Ft, -1);
    addb(rb + 3, nd[1]->base, Ft, 1);
  }
  for (int i = 0; i < 6; ++i) {
    at(clamp_ + i, nodes_[0].base + i) += 1.0;
    at(mom_row(nodes_[0]) + i, clamp_ + i) += 1.0;
  }
  return J;
}

// Dense LU with partial pivoting; f becomes the solution.
void CantileverModel::solve(std::vector<double>& J, std::vector<double>& f) const {
  const int n = n_;
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int r = k + 1; r < n; ++r)
      if (std::fabs(J[static_cast<std::size_t>(r) * n + k]) > std::fabs(J[static_cast<std::size_t>(p) * n + k])) p = r;
    if (J[static_cast<std::size_t>(p) * n + k] == 0.0) throw std::runtime_error("cantilever: singular Jacobian");
    if (p != k) {
      for (int c = 0; c < n; ++c) std::swap(J[static_cast<std::size_t>(p) * n + c], J[static_cast<std::size_t>(k) * n + c]);
      std::swap(f[p], f[k]);
    }
    const double piv = J[static_cast<std::size_t>(k) * n + k];
    for (int r = k + 1; r < n; ++r) {
      const double m = J[static_cast<std::size_t>(r) * n + k] / piv;
      if (m == 0.0) continue;
      for (int c = k; c < n; ++c) J[static_cast<std::size_t>(r) * n + c] -= m * J[static_cast<std::size_t>(k) * n + c];
      f[r] -= m * f[k];
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    double s = f[k];
    for (int c = k + 1; c < n; ++c) s -= J[static_cast<std::size_t>(k) * n + c] * f[c];
    f[k] = s / J[static_cast<std::size_t>(k) * n + k];
  }
}

int CantileverModel::derivatives(const NodalLoads& loads, double dt, int min_updates, int max_updates) {
  const double dcoef = spec_.derivatives_coefficient * dt;
  int it = 0;
  for (;; ++it) {
    std::vector<double> f = residual(loads, dcoef, !beams_fresh_);
    beams_fresh_ = false;
    double r2 = 0;
    for (double x : f) r2 += x * x;
    if (std::sqrt(r2) <= spec_.derivatives_tolerance && it >= min_updates) break;
    if (it >= max_updates)
      throw std::runtime_error("Initial derivatives calculation does not converge in " + std::to_string(max_updates) +
                               " iterations");
    std::vector<double> J = jacobian(dcoef);
    solve(J, f);
    for (int i = 0; i < n_; ++i) {
      if (algebraic_[i]) {
        X_[i] += f[i];
        XP_[i] += dcoef * f[i];
      } else {
        XP_[i] += f[i];
        X_[i] += dcoef * f[i];
      }
    }
    for (const Node& n : nodes_)  // MBDyn's DerivativesUpdate: the nodes keep their initial kinematics
      for (int i = 0; i < 3; ++i) {
        X_[n.base + i] = n.x[i];
        X_[n.base + 3 + i] = n.g[i];
        XP_[n.base + i] = n.v[i];
        XP_[n.base + 3 + i] = n.gp[i];
      }
  }
  accept();
  return it;
}

void CantileverModel::begin_step(double dt) {
  h_ = 0.5 * dt;
  for (Node& n : nodes_) {  // BeforePredict: g restarts from the converged pose, its rate is w
    for (int i = 0; i < 3; ++i) {
      X_[n.base + 3 + i] = 0.0;
      XP_[n.base + 3 + i] = n.w[i];
    }
    n.RPrev = n.R;
  }
  for (int i = 0; i < n_; ++i)  // crank nicolson predictor
    if (!algebraic_[i]) X_[i] = X_[i] + h_ * (XP_[i] + XP_[i]);
  for (Node& n : nodes_) {  // AfterPredict
    for (int i = 0; i < 3; ++i) {
      n.x[i] = X_[n.base + i];
      n.v[i] = XP_[n.base + i];
      n.gRef[i] = X_[n.base + 3 + i];
    }
    V3 gpref;
    for (int i = 0; i < 3; ++i) gpref[i] = XP_[n.base + 3 + i];
    n.R = multiply(cayley_rotation(n.gRef), n.RPrev);
    n.w = rotate_vector(cayley_g_matrix(n.gRef), gpref);
    for (int i = 0; i < 3; ++i) X_[n.base + 3 + i] = XP_[n.base + 3 + i] = 0.0;
    n.g = n.gp = V3{0, 0, 0};
    n.RRef = n.R;
    n.WRef = n.w;
  }
  for (Beam& e : beams_) beam_after_predict(e);
  beams_fresh_ = false;
}

double CantileverModel::residual_norm(const NodalLoads& loads) {
  const std::vector<double> f = residual(loads, h_, true);
  double r2 = 0;
  for (double x : f) r2 += x * x;
  return std::sqrt(r2);
}

void CantileverModel::update(const NodalLoads& loads) {
  std::vector<double> f = residual(loads, h_, true);
  std::vector<double> J = jacobian(h_);
  solve(J, f);
  for (int i = 0; i < n_; ++i) {
    if (algebraic_[i]) {
      X_[i] += f[i];
      XP_[i] += h_ * f[i];
    } else {
      XP_[i] += f[i];
      X_[i] += h_ * f[i];
    }
  }
  nodes_from_state();
}

void CantileverModel::accept() {
  for (Beam& e : beams_) {
    e.RPrev = e.R;
    e.kappa_prev = e.kappa;
  }
}

}  // namespace dembridge::mbdyn::testpeer
