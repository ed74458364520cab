// Free rigid bodies integrated the way MBDyn 1.7.3 integrates dynamic structural nodes, each with
// a `body` of mass m and isotropic inertia J centred on the node, under `method: crank nicolson`
// (learnt from MBDyn's strnode/autostr sources and checked against the recorded refnode_forces
// runs). Per node: position x (derivative v), orientation R, momentum B and momenta moment G
// about the node (derivatives B', G'); the equations are B = m v, G = J w, B' = F, G' + v x B = M.
//   initial derivatives: x, R, v, w kept; B' = F, B = m v + c F, G' = M, G = J w + c G'
//                        (c = derivatives coefficient * dt);
//   predictor:  x = x_ + T v_, v = v_, B = B_ + T B'_, g = T w_ (Cayley-Gibbs-Rodrigues),
//               R = Rd(g) R_, w = Gm(g) w_ (Gm(g) = 4/(4 + g.g) (I + g x / 2));
//   corrector:  an increment g (and its rate g', g = T/2 g') from the predicted pose:
//               R = Rd(g) Rp, w = Gm(g) g' + Rd(g) wp; B = B_ + T/2 (B'_ + F), G the same with
//               G' = M - v x B; v = B / m, w = G / J; x = xp + T/2 (v - vp).
// Rd(g) = I + 4/(4 + g.g) (g x + (g x)^2 / 2). MBDyn's external loads have no Jacobian: each of
// its Newton updates solves the momentum balances for the loads at the previous iterate (the
// prediction first), with v x B linearised at that iterate and g' advanced by one Newton step
// with the Jacobian I - (T/2) w x (w the iterate's angular velocity); it stops at the first
// iterate whose residual is within `tolerance`. So does this model, update by update, which is
// what makes a tight step's iterates (sent after every update) those MBDyn sends: solving the
// balances exactly instead misses the recorded first iterates by 1e-11, the next ones by 1e-13.
#pragma once

#include <functional>
#include <utility>
#include <vector>

#include "testpeer_wire.h"

namespace dembridge::mbdyn::testpeer {

struct FreeBody {
  double mass = 1, inertia = 1;
  V3 x{}, v{}, w{};
  Mat3 R{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  V3 B{}, G{}, Bp{}, Gp{};
};

// Loads on every body (global force, moment about the node), from the bodies' current states.
using BodyLoadsLaw = std::function<void(const std::vector<FreeBody>&, std::vector<V3>& force, std::vector<V3>& moment)>;

class FreeBodiesModel {
 public:
  // tolerance: MBDyn's `tolerance` (the residual norm that ends its Newton iterations)
  FreeBodiesModel(std::vector<FreeBody> bodies, V3 gravity, double derivatives_coefficient, double tolerance);
  const std::vector<FreeBody>& state() const { return bodies_; }
  // The initial-derivatives solve at t0 with these loads (gravity added here).
  void derivatives(const BodyLoadsLaw& loads, double dt);
  // The predicted state of the next step (what MBDyn sends after its predictor).
  std::vector<FreeBody> predict(double dt) const;
  // Solves the step from the current state for the loads law and makes it current (MBDyn's
  // Newton iterations below, until the residual is within tolerance).
  void step(const BodyLoadsLaw& loads, double dt);

  // The same step one Newton iteration at a time: begin_step puts the iterate at the prediction;
  // update solves the momentum balances for the loads at the iterate; residual is the mismatch of
  // the loads at the iterate with the B', G' it was solved with; accept makes the iterate current.
  void begin_step(double dt);
  const std::vector<FreeBody>& iterate() const { return cur_; }
  void update(const BodyLoadsLaw& loads);
  double residual(const BodyLoadsLaw& loads) const;
  void accept() { bodies_ = cur_; }
  double tolerance() const { return tolerance_; }

 private:
  void add_gravity(std::vector<V3>& force) const;
  void evaluate(const BodyLoadsLaw& loads, std::vector<V3>& f, std::vector<V3>& m) const;
  std::vector<FreeBody> pred_, cur_;  // the step's prediction and current iterate
  std::vector<V3> gdot_;              // the iterate's rotation-increment rates
  double dt_ = 0;
  std::vector<FreeBody> bodies_;
  V3 gravity_;
  double c_, tolerance_;
};

// Cayley-Gibbs-Rodrigues rotation and the matrix G of w = G(g) g' (MBDyn's conventions).
Mat3 cayley_rotation(const V3& g);
V3 cayley_g_times(const V3& g, const V3& gdot);

}  // namespace dembridge::mbdyn::testpeer
