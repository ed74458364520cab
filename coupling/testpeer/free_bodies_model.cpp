#include "free_bodies_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dembridge::mbdyn::testpeer {

namespace {
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double det3(const Mat3& A) {
  return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
         A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
}
V3 solve3(const Mat3& A, const V3& b) {
  const double d = det3(A);
  V3 x;
  for (int c = 0; c < 3; ++c) {
    Mat3 M = A;
    for (int r = 0; r < 3; ++r) M[r][c] = b[r];
    x[c] = det3(M) / d;
  }
  return x;
}
}  // namespace

Mat3 cayley_rotation(const V3& g) {
  const double d = 4.0 / (4.0 + dot(g, g));
  const Mat3 gx{{{0, -g[2], g[1]}, {g[2], 0, -g[0]}, {-g[1], g[0], 0}}};
  const Mat3 gxgx = multiply(gx, gx);
  Mat3 R{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R[i][j] = (i == j ? 1.0 : 0.0) + d * (gx[i][j] + 0.5 * gxgx[i][j]);
  return R;
}

V3 cayley_g_times(const V3& g, const V3& gdot) {
  const double d = 4.0 / (4.0 + dot(g, g));
  const V3 c = cross(g, gdot);
  return {d * (gdot[0] + 0.5 * c[0]), d * (gdot[1] + 0.5 * c[1]), d * (gdot[2] + 0.5 * c[2])};
}

FreeBodiesModel::FreeBodiesModel(std::vector<FreeBody> bodies, V3 gravity, double derivatives_coefficient,
                                 double tolerance)
    : bodies_(std::move(bodies)), gravity_(gravity), c_(derivatives_coefficient), tolerance_(tolerance) {
  for (FreeBody& b : bodies_)
    for (int k = 0; k < 3; ++k) {
      b.B[k] = b.mass * b.v[k];
      b.G[k] = b.inertia * b.w[k];
      b.Bp[k] = b.Gp[k] = 0;
    }
}

void FreeBodiesModel::add_gravity(std::vector<V3>& force) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    for (int k = 0; k < 3; ++k) force[i][k] += bodies_[i].mass * gravity_[k];
}

void FreeBodiesModel::derivatives(const BodyLoadsLaw& loads, double dt) {
  std::vector<V3> f(bodies_.size(), V3{}), m(bodies_.size(), V3{});
  loads(bodies_, f, m);
  add_gravity(f);
  const double c = c_ * dt;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    FreeBody& b = bodies_[i];
    for (int k = 0; k < 3; ++k) {
      b.Bp[k] = f[i][k];
      b.B[k] = b.mass * b.v[k] + c * f[i][k];
    }
    // G' = M: the c v x F of G' + v x B = M is absent from MBDyn's initial derivatives (measured:
    // with it, the recorded angular velocities are missed by 2e-12 from step 2 on)
    for (int k = 0; k < 3; ++k) {
      b.Gp[k] = m[i][k];
      b.G[k] = b.inertia * b.w[k] + c * b.Gp[k];
    }
  }
}

std::vector<FreeBody> FreeBodiesModel::predict(double dt) const {
  std::vector<FreeBody> out = bodies_;
  for (FreeBody& b : out) {
    V3 g;
    for (int k = 0; k < 3; ++k) {
      b.x[k] += dt * b.v[k];
      b.B[k] += dt * b.Bp[k];
      b.G[k] += dt * b.Gp[k];
      g[k] = dt * b.w[k];
    }
    b.R = multiply(cayley_rotation(g), b.R);
    b.w = cayley_g_times(g, b.w);
  }
  return out;
}

void FreeBodiesModel::begin_step(double dt) {
  dt_ = dt;
  pred_ = predict(dt);
  cur_ = pred_;
  gdot_.assign(bodies_.size(), V3{});
}

void FreeBodiesModel::evaluate(const BodyLoadsLaw& loads, std::vector<V3>& f, std::vector<V3>& m) const {
  f.assign(cur_.size(), V3{});
  m.assign(cur_.size(), V3{});
  loads(cur_, f, m);
  add_gravity(f);
}

double FreeBodiesModel::residual(const BodyLoadsLaw& loads) const {
  std::vector<V3> f, m;
  evaluate(loads, f, m);
  double r2 = 0;
  for (std::size_t i = 0; i < cur_.size(); ++i) {
    const V3 vxB = cross(cur_[i].v, cur_[i].B);
    for (int k = 0; k < 3; ++k) {
      const double rf = f[i][k] - cur_[i].Bp[k], rm = m[i][k] - cur_[i].Gp[k] - vxB[k];
      const double rg = cur_[i].G[k] - cur_[i].inertia * cur_[i].w[k];  // w(g') linearised in the update
      r2 += rf * rf + rm * rm + rg * rg;
    }
  }
  return std::sqrt(r2);
}

void FreeBodiesModel::update(const BodyLoadsLaw& loads) {
  const double h = 0.5 * dt_;
  std::vector<V3> f, m;
  evaluate(loads, f, m);
  for (std::size_t i = 0; i < cur_.size(); ++i) {
    const FreeBody& o = bodies_[i];
    const FreeBody& p = pred_[i];
    FreeBody& b = cur_[i];
    const V3 B_old = b.B;
    V3 v;
    for (int k = 0; k < 3; ++k) {
      b.Bp[k] = f[i][k];
      b.B[k] = o.B[k] + h * (o.Bp[k] + f[i][k]);
      v[k] = b.B[k] / b.mass;
    }
    // v x B linearised at the iterate (a Newton update)
    V3 dv, dB;
    for (int k = 0; k < 3; ++k) {
      dv[k] = v[k] - b.v[k];
      dB[k] = b.B[k] - B_old[k];
    }
    const V3 p0 = cross(b.v, B_old), p1 = cross(dv, B_old), p2 = cross(b.v, dB);
    const V3 vxB{p0[0] + p1[0] + p2[0], p0[1] + p1[1] + p2[1], p0[2] + p1[2] + p2[2]};
    V3 w;
    for (int k = 0; k < 3; ++k) {
      b.Gp[k] = m[i][k] - vxB[k];
      b.G[k] = o.G[k] + h * (o.Gp[k] + b.Gp[k]);
      w[k] = b.G[k] / b.inertia;
    }
    // One Newton update of g' towards Gm(h g') g' + Rd(h g') wp = w with MBDyn's Jacobian
    // I - h w x (exact at the prediction, g' = 0)
    V3 gd = gdot_[i], g;
    for (int k = 0; k < 3; ++k) g[k] = h * gd[k];
    const V3 a0 = cayley_g_times(g, gd), r0 = rotate_vector(cayley_rotation(g), p.w);
    const V3 e{w[0] - a0[0] - r0[0], w[1] - a0[1] - r0[1], w[2] - a0[2] - r0[2]};
    const V3 c{h * b.w[0], h * b.w[1], h * b.w[2]};
    // (I - c x) d = e: Cramer on the 3 x 3
    const Mat3 A{{{1, c[2], -c[1]}, {-c[2], 1, c[0]}, {c[1], -c[0], 1}}};
    const V3 d = solve3(A, e);
    for (int k = 0; k < 3; ++k) gd[k] += d[k];
    gdot_[i] = gd;
    for (int k = 0; k < 3; ++k) {
      b.v[k] = v[k];
      b.x[k] = p.x[k] + h * (v[k] - p.v[k]);
      g[k] = h * gd[k];
    }
    const Mat3 Rd = cayley_rotation(g);
    b.R = multiply(Rd, p.R);
    const V3 a = cayley_g_times(g, gd), r = rotate_vector(Rd, p.w);
    for (int k = 0; k < 3; ++k) b.w[k] = a[k] + r[k];
  }
}

void FreeBodiesModel::step(const BodyLoadsLaw& loads, double dt) {
  begin_step(dt);
  for (int pass = 0;; ++pass) {
    if (pass > 0 && residual(loads) <= tolerance_) break;
    if (pass >= 30) throw std::runtime_error("free bodies: no convergence in 30 iterations");
    update(loads);
  }
  accept();
}

}  // namespace dembridge::mbdyn::testpeer
