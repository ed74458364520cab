#include "free_modal_body_model.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace dembridge::mbdyn::testpeer {

namespace {

V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 scale(const V3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Mat3 skew(const V3& v) { return Mat3{{{0, -v[2], v[1]}, {v[2], 0, -v[0]}, {-v[1], v[0], 0}}}; }
Mat3 madd(const Mat3& A, const Mat3& B, double s = 1.0) {
  Mat3 C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C[i][j] = A[i][j] + s * B[i][j];
  return C;
}
Mat3 mscale(const Mat3& A, double s) { return madd(Mat3{}, A, s); }

// MBDyn's Cayley-Gibbs-Rodrigues rotation Rd(g) and G(g) (w = G(g) g')
Mat3 rot_cgr(const V3& g) {
  const double d = 4.0 / (4.0 + dot(g, g));
  const Mat3 gx = skew(g);
  return madd(madd(Mat3{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, gx, d), multiply(gx, gx), 0.5 * d);
}
Mat3 g_cgr(const V3& g) {
  const double d = 4.0 / (4.0 + dot(g, g));
  return madd(mscale(Mat3{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, d), skew(g), 0.5 * d);
}

V3 seg(const std::vector<double>& v, std::size_t i) { return {v[i], v[i + 1], v[i + 2]}; }
void put(std::vector<double>& v, std::size_t i, const V3& a) {
  for (int k = 0; k < 3; ++k) v[i + k] = a[k];
}

// Dense Gaussian elimination with partial pivoting, A (n x n, row major) x = b in place.
void solve_dense(std::vector<double> A, std::vector<double>& b) {
  const std::size_t n = b.size();
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t p = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::fabs(A[r * n + c]) > std::fabs(A[p * n + c])) p = r;
    if (A[p * n + c] == 0.0) throw std::runtime_error("modal body: singular Jacobian");
    if (p != c) {
      for (std::size_t k = 0; k < n; ++k) std::swap(A[p * n + k], A[c * n + k]);
      std::swap(b[p], b[c]);
    }
    for (std::size_t r = c + 1; r < n; ++r) {
      const double f = A[r * n + c] / A[c * n + c];
      if (f == 0.0) continue;
      for (std::size_t k = c; k < n; ++k) A[r * n + k] -= f * A[c * n + k];
      b[r] -= f * b[c];
    }
  }
  for (std::size_t c = n; c-- > 0;) {
    double s = b[c];
    for (std::size_t k = c + 1; k < n; ++k) s -= A[c * n + k] * b[k];
    b[c] = s / A[c * n + c];
  }
}

}  // namespace

FreeModalBodyModel::FreeModalBodyModel(const ModalFemData& fem, int origin, V3 x0, V3 v0, V3 w0,
                                       std::vector<double> q0, std::vector<double> qdot0, double tolerance)
    : nm_(fem.modes()), n_(12 + 2 * fem.modes()), tol_(tolerance) {
  if (q0.size() != nm_ || qdot0.size() != nm_) throw std::runtime_error("modal body: one q0, q'0 per mode");
  const std::size_t nn = fem.position.size();
  const V3 o = origin >= 0 ? fem.position[static_cast<std::size_t>(origin)] : V3{};
  inv3_.assign(nm_, V3{});
  inv4_.assign(nm_, V3{});
  inv11_.assign(nm_, V3{});
  inv5_.assign(nm_ * nm_, V3{});
  inv8_.assign(nm_, Mat3{});
  inv10_.assign(nm_, Mat3{});
  // MBDyn's invariants from the lumped masses (modal.cc: Inv1..Inv11 without Inv9)
  for (std::size_t i = 0; i < nn; ++i) {
    const double mi = fem.node_mass[i];
    const V3 u{fem.position[i][0] - o[0], fem.position[i][1] - o[1], fem.position[i][2] - o[2]};
    const Mat3 Ji{{{fem.node_inertia[i][0], 0, 0}, {0, fem.node_inertia[i][1], 0}, {0, 0, fem.node_inertia[i][2]}}};
    const Mat3 ux = skew(u);
    mass_ += mi;
    inv7_ = madd(inv7_, madd(Ji, multiply(ux, ux), -mi));
    inv2_ = add(inv2_, scale(u, mi));
    for (std::size_t j = 0; j < nm_; ++j) {
      const V3& pt = fem.shape_t[j][i];
      const V3& pr = fem.shape_r[j][i];
      inv3_[j] = add(inv3_[j], scale(pt, mi));
      const V3 jr = rotate_vector(Ji, pr);
      inv4_[j] = add(inv4_[j], add(rotate_vector(mscale(ux, mi), pt), jr));
      inv11_[j] = add(inv11_[j], jr);
      const Mat3 ptx = skew(scale(pt, mi));
      for (std::size_t k = 0; k < nm_; ++k) inv5_[j * nm_ + k] = add(inv5_[j * nm_ + k], rotate_vector(ptx, fem.shape_t[k][i]));
      inv8_[j] = madd(inv8_[j], multiply(ux, ptx), -1.0);
      Mat3 i10;  // [pr x] applied to each column of Ji
      for (int c = 0; c < 3; ++c) {
        const V3 col = cross(pr, V3{Ji[0][c], Ji[1][c], Ji[2][c]});
        for (int r = 0; r < 3; ++r) i10[r][c] = col[r];
      }
      inv10_[j] = madd(inv10_[j], i10);
    }
  }
  M_ = fem.mass;
  K_ = fem.stiffness;
  C_ = fem.damping;
  X_.assign(n_, 0.0);
  XP_.assign(n_, 0.0);
  put(X_, 0, x0);
  put(XP_, 0, v0);  // the node's velocity x'; g' = 0 with w_ref = w0 gives w = w0
  put(X_, 6, v0);
  put(X_, 9, w0);
  for (std::size_t j = 0; j < nm_; ++j) {
    X_[12 + j] = q0[j];
    X_[12 + nm_ + j] = qdot0[j];
  }
  Rref_ = Mat3{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  Wref_ = w0;
  a_el_ = std::move(q0);
  b_el_ = std::move(qdot0);
  f_.assign(n_, 0.0);
}

ModalBodyKinematics FreeModalBodyModel::kinematics() const {
  ModalBodyKinematics k;
  const V3 g = seg(X_, 3), gp = seg(XP_, 3);
  const Mat3 Rd = rot_cgr(g);
  k.x = seg(X_, 0);
  k.R = multiply(Rd, Rref_);
  k.v = seg(XP_, 0);
  k.w = add(rotate_vector(g_cgr(g), gp), rotate_vector(Rd, Wref_));
  k.q = a_el_;
  k.qdot = b_el_;
  return k;
}

void FreeModalBodyModel::predict(double dt) {
  const ModalBodyKinematics k = kinematics();
  h_ = 0.5 * dt;
  // every dof: X = X_ + dt X'_, X' = X'_; the rotation: g_ref = dt w_, then g = 0 from the new pose
  for (std::size_t i = 0; i < n_; ++i) X_[i] += dt * XP_[i];
  const V3 gref = scale(k.w, dt);
  Rref_ = multiply(rot_cgr(gref), k.R);
  Wref_ = rotate_vector(g_cgr(gref), k.w);
  put(X_, 3, V3{});
  put(XP_, 3, V3{});
}

double FreeModalBodyModel::assemble(const ModalLoads& L) {
  const std::size_t m = nm_;
  const V3 g = seg(X_, 3), gp = seg(XP_, 3), v = seg(X_, 6), w = seg(X_, 9);
  const V3 xp = seg(XP_, 0), vp = seg(XP_, 6), wp = seg(XP_, 9);
  std::vector<double> a(X_.begin() + 12, X_.begin() + 12 + m), b(X_.begin() + 12 + m, X_.end());
  std::vector<double> ap(XP_.begin() + 12, XP_.begin() + 12 + m), bp(XP_.begin() + 12 + m, XP_.end());
  const Mat3 Rd = rot_cgr(g);
  R_ = multiply(Rd, Rref_);
  const Mat3 RT = transpose(R_);
  V3 i3a{}, i3b{}, i3bp{};
  Mat3 i8a{}, i10b{};
  inv8b_ = Mat3{};
  inv5a_.assign(m, V3{});
  std::vector<V3> inv5b(m, V3{});
  for (std::size_t j = 0; j < m; ++j) {
    i3a = add(i3a, scale(inv3_[j], a[j]));
    i3b = add(i3b, scale(inv3_[j], b[j]));
    i3bp = add(i3bp, scale(inv3_[j], bp[j]));
    i8a = madd(i8a, inv8_[j], a[j]);
    inv8b_ = madd(inv8b_, inv8_[j], b[j]);
    i10b = madd(i10b, inv10_[j], b[j]);
    for (std::size_t k = 0; k < m; ++k) {
      inv5a_[k] = add(inv5a_[k], scale(inv5_[j * m + k], a[j]));
      inv5b[k] = add(inv5b[k], scale(inv5_[j * m + k], b[j]));
    }
  }
  inv3b_ = i3b;
  J_ = multiply(multiply(R_, madd(madd(inv7_, i8a), transpose(i8a))), RT);
  S_ = rotate_vector(R_, add(inv2_, i3a));
  const V3 RTw = rotate_vector(RT, w);
  // forces of inertia
  V3 FT = add(add(scale(vp, mass_), scale(cross(S_, wp), -1.0)), cross(w, cross(w, S_)));
  FT = add(FT, add(rotate_vector(R_, i3bp), scale(cross(w, rotate_vector(R_, i3b)), 2.0)));
  V3 MT = add(add(cross(S_, vp), rotate_vector(J_, wp)), cross(w, rotate_vector(J_, w)));
  V3 inv4bp{}, inv5abp{}, inv11b{};
  for (std::size_t j = 0; j < m; ++j) {
    inv4bp = add(inv4bp, scale(inv4_[j], bp[j]));
    inv5abp = add(inv5abp, scale(inv5a_[j], bp[j]));
    inv11b = add(inv11b, scale(inv11_[j], b[j]));
  }
  MT = add(MT, add(rotate_vector(R_, inv4bp), rotate_vector(R_, inv5abp)));
  MT = add(MT, rotate_vector(R_, rotate_vector(inv8b_, scale(RTw, 2.0))));
  // rotary inertia of the FEM nodes (zero without rotation shapes), as MBDyn writes it
  const V3 vt = add(rotate_vector(madd(i10b, transpose(i10b)), RTw), cross(w, rotate_vector(R_, inv11b)));
  MT = add(MT, rotate_vector(R_, vt));
  put(f_, 0, add(v, scale(xp, -1.0)));
  put(f_, 3, add(w, scale(add(rotate_vector(g_cgr(g), gp), rotate_vector(Rd, Wref_)), -1.0)));
  put(f_, 6, add(L.force, scale(FT, -1.0)));
  put(f_, 9, add(L.moment, scale(MT, -1.0)));
  for (std::size_t j = 0; j < m; ++j) {
    double d = 0;
    for (std::size_t k = 0; k < m; ++k) d -= M_[j * m + k] * bp[k] + C_[j * m + k] * b[k] + K_[j * m + k] * a[k];
    d -= dot(rotate_vector(R_, inv3_[j]), vp);
    d -= 2.0 * dot(rotate_vector(R_, inv5b[j]), w);
    d -= dot(rotate_vector(R_, add(inv4_[j], inv5a_[j])), wp);
    d += dot(w, rotate_vector(R_, rotate_vector(madd(transpose(inv8_[j]), inv10_[j]), RTw)));
    f_[12 + m + j] = d + L.p[j];
    f_[12 + j] = b[j] - ap[j];
  }
  a_el_ = a;
  b_el_ = b;
  double r2 = 0;
  for (double r : f_) r2 += r * r;
  return std::sqrt(r2);
}

// MBDyn's Modal::AssJac for a free modal node without interface nodes (d(-f)/dX' + dCoef d(-f)/dX,
// as MBDyn approximates it)
void FreeModalBodyModel::jacobian(std::vector<double>& W) const {
  const std::size_t n = n_, m = nm_;
  W.assign(n * n, 0.0);
  auto add3 = [&](std::size_t r, std::size_t c, const Mat3& A) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) W[(r + i) * n + c + j] += A[i][j];
  };
  const V3& wr = Wref_;
  const Mat3 I{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  add3(6, 6, mscale(I, mass_));
  add3(6, 9, madd(madd(multiply(skew(S_), skew(scale(wr, h_))), multiply(skew(wr), skew(scale(S_, 2.0 * h_))), -1.0),
                  skew(S_), -1.0));
  add3(9, 6, skew(S_));
  add3(9, 9, madd(J_, madd(multiply(skew(wr), J_), skew(rotate_vector(J_, wr)), -1.0), h_));
  for (std::size_t i = 0; i < 6; ++i) {
    W[i * n + i] += 1.0;
    W[i * n + 6 + i] -= h_;
  }
  add3(3, 3, mscale(skew(scale(wr, h_)), -1.0));
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t ri = 12 + i;
    W[ri * n + ri] = 1.0;
    W[ri * n + ri + m] = -h_;
    for (std::size_t j = 0; j < m; ++j) {
      W[(ri + m) * n + 12 + j] = h_ * K_[i * m + j];
      W[(ri + m) * n + 12 + m + j] = M_[i * m + j] + h_ * C_[i * m + j];
    }
  }
  for (std::size_t j = 0; j < m; ++j) {
    const V3 j13 = rotate_vector(R_, inv3_[j]);
    const V3 j23 = add(rotate_vector(R_, inv4_[j]), rotate_vector(R_, inv5a_[j]));
    for (int i = 0; i < 3; ++i) {
      W[(6 + i) * n + 12 + m + j] += j13[i];
      W[(12 + m + j) * n + 6 + i] += j13[i];
      W[(9 + i) * n + 12 + m + j] += j23[i];
      W[(12 + m + j) * n + 9 + i] += j23[i];
    }
  }
  add3(6, 9, mscale(skew(rotate_vector(R_, scale(inv3b_, 2.0 * h_))), -1.0));
  add3(9, 9, multiply(R_, multiply(inv8b_, mscale(transpose(R_), 2.0 * h_))));
}

void FreeModalBodyModel::update() {
  std::vector<double> J;
  jacobian(J);
  std::vector<double> d = f_;
  solve_dense(std::move(J), d);
  for (std::size_t i = 0; i < n_; ++i) {
    XP_[i] += d[i];
    X_[i] += h_ * d[i];
  }
}

std::vector<double> FreeModalBodyModel::qddot() const {
  return std::vector<double>(XP_.begin() + 12 + nm_, XP_.end());
}

}  // namespace dembridge::mbdyn::testpeer
