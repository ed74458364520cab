// A free modal body as MBDyn 1.7.3 solves it: a `modal` joint (FEM file, no interface nodes) on a
// `modal` structural node, `method: crank nicolson`, learnt from MBDyn's modal.cc / strnode.cc and
// checked against the recorded `external modal` runs (tests/data/mbdyn-ext/modal_body).
// Unknowns (all differential, MBDyn's order): node x, g (rotation increment, Cayley-Gibbs-Rodrigues,
// from the predicted pose), v, w, then the modes q, q' (MBDyn's a, b). Equations:
//   v = x',  w = G(g) g' + Rd(g) w_ref,  q' = b,
//   m v' - S x w' + w x (w x S) + R I3 b' + 2 w x (R I3 b) = F,
//   S x v' + J w' + w x J w + R (I4 + I5 a) b' + 2 R I8(b) R^T w (+ rotary terms I10, I11) = M,
//   M_q b' + C b + K a + (R I3)^T v' + (R (I4 + I5 a))^T w' + 2 (R I5(b))^T w - w.(R I8_j^T R^T w) = p,
// with S = R (I2 + I3 a), J = R (I7 + I8(a) + I8(a)^T) R^T (MBDyn's invariants from the lumped
// masses; I9 is off by default and not modelled). Each Newton update solves MBDyn's own Jacobian
// (not the exact one: its rotation and Coriolis terms are taken at the reference w and g = 0), so the
// iterates (what a tight coupling sends) are MBDyn's; it stops when the residual's 2-norm is within
// `tolerance`. The loads F, M (global, about the node) and p enter without Jacobian.
// The element's q, q' that MBDyn sends are those of its last residual (one iterate behind).
#pragma once

#include <string>
#include <vector>

#include "modal_fem_file.h"
#include "testpeer_wire.h"

namespace dembridge::mbdyn::testpeer {

struct ModalLoads {
  V3 force{}, moment{};
  std::vector<double> p;
};

struct ModalBodyKinematics {
  V3 x{}, v{}, w{};
  Mat3 R{};
  std::vector<double> q, qdot;
};

class FreeModalBodyModel {
 public:
  // origin: index of the FEM node put on the modal node (MBDyn's `origin node`), or -1.
  // The node starts at x0 with R = I, velocity v0, angular velocity w0; the modes at q0, qdot0.
  FreeModalBodyModel(const ModalFemData& fem, int origin, V3 x0, V3 v0, V3 w0, std::vector<double> q0,
                     std::vector<double> qdot0, double tolerance);
  std::size_t modes() const { return nm_; }
  // What MBDyn's external modal element sends now: the node's pose and rates, the element's q, q'.
  ModalBodyKinematics kinematics() const;
  // MBDyn's crank nicolson predictor from the last accepted state.
  void predict(double dt);
  // Assembles the residual at the current iterate for these loads (also what the element sends
  // next); returns its 2-norm.
  double assemble(const ModalLoads& loads);
  // One Newton update with MBDyn's Jacobian at the iterate of the last assemble().
  void update();
  double tolerance() const { return tol_; }
  std::vector<double> qddot() const;  // b' of the current iterate

 private:
  void jacobian(std::vector<double>& J) const;
  std::size_t nm_, n_;
  // invariants
  double mass_ = 0;
  V3 inv2_{};
  Mat3 inv7_{};
  std::vector<V3> inv3_, inv4_, inv11_;  // per mode
  std::vector<V3> inv5_;                 // [j * nm + k]
  std::vector<Mat3> inv8_, inv10_;       // per mode
  std::vector<double> M_, K_, C_;
  // state: X, XP (12 + 2 nm), the reference pose of the rotation increment
  std::vector<double> X_, XP_, f_;
  Mat3 Rref_{};
  V3 Wref_{};
  double h_ = 0;  // dCoef = dt / 2
  double tol_;
  // from the last assemble(): the element's q, q' and what its Jacobian uses
  std::vector<double> a_el_, b_el_;
  Mat3 R_{}, J_{};
  V3 S_{};
  Mat3 inv8b_{};
  std::vector<V3> inv5a_;  // per mode k: sum_j I5_jk a_j
  V3 inv3b_{};
};

}  // namespace dembridge::mbdyn::testpeer
