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

void FreeBodiesModel::step(const BodyLoadsLaw& loads, double dt) {
  const std::vector<FreeBody> pred = predict(dt);
  const double h = 0.5 * dt;
  const std::size_t n = bodies_.size();
  std::vector<V3> gdot(n, V3{}), f(n), m(n);
  std::vector<FreeBody> cur = pred;
  auto place = [&](std::size_t i, const V3& v, const V3& gd) {
    FreeBody& b = cur[i];
    const FreeBody& p = pred[i];
    V3 g;
    for (int k = 0; k < 3; ++k) {
      b.v[k] = v[k];
      b.x[k] = p.x[k] + h * (v[k] - p.v[k]);
      g[k] = h * gd[k];
    }
    const Mat3 Rd = cayley_rotation(g);
    b.R = multiply(Rd, p.R);
    const V3 a = cayley_g_times(g, gd), r = rotate_vector(Rd, p.w);
    for (int k = 0; k < 3; ++k) b.w[k] = a[k] + r[k];
  };
  // MBDyn's Newton iterations: the loads have no Jacobian, so each update solves the momentum
  // balances (exactly here) for the loads at the previous iterate (the prediction first), and
  // B', G' keep those loads. It stops once the residual at the new iterate, the mismatch of the
  // loads there with B', G', is within tolerance (2 updates on the recorded runs).
  for (int pass = 0;; ++pass) {
    if (pass >= 30) throw std::runtime_error("free bodies: no convergence in 30 iterations");
    std::fill(f.begin(), f.end(), V3{});
    std::fill(m.begin(), m.end(), V3{});
    loads(cur, f, m);
    add_gravity(f);
    if (pass > 0) {
      double r2 = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const V3 vxB = cross(cur[i].v, cur[i].B);
        for (int k = 0; k < 3; ++k) {
          const double rf = f[i][k] - cur[i].Bp[k], rm = m[i][k] - cur[i].Gp[k] - vxB[k];
          r2 += rf * rf + rm * rm;
        }
      }
      if (std::sqrt(r2) <= tolerance_) break;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const FreeBody& o = bodies_[i];
      FreeBody& b = cur[i];
      V3 v;
      for (int k = 0; k < 3; ++k) {
        b.Bp[k] = f[i][k];
        b.B[k] = o.B[k] + h * (o.Bp[k] + f[i][k]);
        v[k] = b.B[k] / b.mass;
      }
      const V3 vxB = cross(v, b.B);
      V3 w;
      for (int k = 0; k < 3; ++k) {
        b.Gp[k] = m[i][k] - vxB[k];
        b.G[k] = o.G[k] + h * (o.Gp[k] + b.Gp[k]);
        w[k] = b.G[k] / b.inertia;
      }
      // g' with Gm(h g') g' + Rd(h g') wp = w, by the fixed point on the Jacobian's leading I
      V3 gd = gdot[i];
      for (int it = 0; it < 50; ++it) {
        V3 g;
        for (int k = 0; k < 3; ++k) g[k] = h * gd[k];
        const V3 a = cayley_g_times(g, gd), r = rotate_vector(cayley_rotation(g), pred[i].w);
        double step = 0;
        for (int k = 0; k < 3; ++k) {
          const double e = a[k] + r[k] - w[k];
          gd[k] -= e;
          step = std::max(step, std::fabs(e));
        }
        if (step <= 1e-18) break;
      }
      gdot[i] = gd;
      place(i, v, gd);
    }
  }
  bodies_ = cur;
}

}  // namespace dembridge::mbdyn::testpeer
