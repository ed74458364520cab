// A cantilever of MBDyn `beam2` elements solved the way MBDyn 1.7.3 solves it (learnt from its
// strnode, autostr, body, beam2, genj (clamp), stepsol and nr sources; checked against the
// recorded mapping_beam runs): node 0 `static` and held by a `clamp`, nodes 1..N-1 `dynamic` with a
// `body` each (mass m, inertia diag(J), no offset), `gravity`, one `beam2` between consecutive
// nodes (no offsets, section orientation eye, `linear elastic generic, diag` law), `crank
// nicolson`. The whole system is MBDyn's: per dynamic node the unknowns x, g (rotation increment
// from the prediction), B, G with their derivatives; per static node x, g; the clamp's reaction
// force and couple (algebraic). Residual and Jacobian are assembled term by term as MBDyn's
// elements assemble them (the beam2's approximate Jacobian, its strain at the mid-point from the
// reference orientation of the step, the curvature accumulated step by step), and each Newton
// update is MBDyn's: J d = f, derivatives += d, states += (dt/2) d. MBDyn stops at the first
// residual norm (Euclidean, all equations) within `tolerance`, typically 1e-10 after 3 updates;
// a tight-coupled step's iterates are sent after every update, so the model must take the same
// updates, not converge further. External loads enter as node forces and moments fixed when
// they are received (MBDyn's external structural mapping: no Jacobian contribution).
#pragma once

#include <array>
#include <vector>

#include "testpeer_wire.h"

namespace dembridge::mbdyn::testpeer {

struct CantileverSpec {
  std::vector<V3> node_x;                // node 0 static and clamped; the others dynamic
  double mass = 1, inertia = 1;          // each dynamic node's body: m, J = diag(inertia)
  std::array<double, 6> stiffness{};     // beam2 `linear elastic generic, diag` EA GA GA GJ EI EI
  V3 gravity{0, 0, 0};
  double derivatives_coefficient = 1e-6;  // MBDyn's default
  double derivatives_tolerance = 1e-6;
  double tolerance = 1e-9;
};

// One node's kinematics as MBDyn reports it.
struct CantileverNode {
  V3 x{}, v{}, w{};
  Mat3 R{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
};

// External loads on every node (global force, moment about the node), node 0 included.
struct NodalLoads {
  std::vector<V3> force, moment;
};

class CantileverModel {
 public:
  explicit CantileverModel(const CantileverSpec& spec);
  std::size_t node_count() const { return nodes_.size(); }
  std::vector<CantileverNode> nodes() const;

  // The initial-derivatives solve at t0 (MBDyn's DerivativeSolver: node kinematics kept, the
  // coefficient derivatives_coefficient * dt). min_updates: MBDyn takes 2 updates under tight
  // coupling (measured: `performed in 2 iterations`), 1 under loose. Returns the updates taken.
  int derivatives(const NodalLoads& loads, double dt, int min_updates, int max_updates);

  // MBDyn's predictor (crank nicolson: derivatives kept, states advanced by dt times them, the
  // rotations by the Cayley-Gibbs-Rodrigues increment dt w); the iterate is then the prediction.
  void begin_step(double dt);
  double residual_norm(const NodalLoads& loads);  // at the iterate
  void update(const NodalLoads& loads);            // one Newton update of the iterate
  void accept();                                   // MBDyn's AfterConvergence

 private:
  struct Node {
    bool dynamic = false;
    int base = 0;  // first unknown (x, g[, B, G])
    V3 x{}, v{}, w{}, g{}, gp{}, gRef{};
    Mat3 R{}, RRef{}, RPrev{};
    V3 WRef{};
  };
  struct Beam {
    int a = 0, b = 0;
    Mat3 R{}, RRef{}, RPrev{};
    V3 p{}, L{}, L0{}, kappa_ref{}, kappa_prev{}, eps{}, kappa{};
    V3 F{}, M{};  // internal actions, global
    std::array<double, 6> DRef[6];
    double dsdxi = 1;
  };

  int mom_row(const Node& n) const { return n.dynamic ? n.base + 6 : n.base; }
  void nodes_from_state();  // MBDyn's StructNode::Update
  void beam_after_predict(Beam& e);
  void beam_residual_update(Beam& e);
  std::vector<double> residual(const NodalLoads& loads, double dcoef, bool update_beams);
  std::vector<double> jacobian(double dcoef) const;
  void solve(std::vector<double>& J, std::vector<double>& f) const;

  CantileverSpec spec_;
  std::vector<Node> nodes_;
  std::vector<Beam> beams_;
  int clamp_ = 0, n_ = 0;
  std::vector<double> X_, XP_;
  std::vector<bool> algebraic_;
  double h_ = 0;  // dt / 2
  bool beams_fresh_ = true;  // MBDyn's bFirstRes at t0: the first residual keeps the construction values
};

}  // namespace dembridge::mbdyn::testpeer
