#include "axis_inertia.h"

#include <Eigen/Dense>

namespace dembridge::torsion {

namespace {
Eigen::Matrix3d to_eigen(const Mat3& m) {
  Eigen::Matrix3d e;
  e << m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8];
  return e;
}
}  // namespace

Mat3 spatial_inverse_inertia(const Mat3& rotation, const Mat3& body_inverse_inertia) {
  const Eigen::Matrix3d L = to_eigen(rotation);
  const Eigen::Matrix3d W = L * to_eigen(body_inverse_inertia) * L.transpose();
  return {W(0, 0), W(0, 1), W(0, 2), W(1, 0), W(1, 1), W(1, 2), W(2, 0), W(2, 1), W(2, 2)};
}

Vec3 axis_inertias(const TorsionFrame& f, const Mat3& w1, const Mat3* w2) {
  Eigen::Matrix3d R;
  R << f.x[0], f.y[0], f.z[0], f.x[1], f.y[1], f.z[1], f.x[2], f.y[2], f.z[2];
  Eigen::Matrix3d W = to_eigen(w1);
  if (w2) W += to_eigen(*w2);
  const Eigen::Matrix3d Mi = (R.transpose() * W * R).inverse();
  return {Mi(0, 0), Mi(1, 1), Mi(2, 2)};
}

Vec3 axis_inertias_parmec(const TorsionFrame& f, const Mat3& body_inv1, const Mat3* body_inv2) {
  Eigen::Matrix3d R;
  R << f.x[0], f.y[0], f.z[0], f.x[1], f.y[1], f.z[1], f.x[2], f.y[2], f.z[2];
  Eigen::Matrix3d Ji = to_eigen(body_inv1);
  if (body_inv2) Ji += to_eigen(*body_inv2);
  const Eigen::Matrix3d Mi = (R * Ji * R.transpose()).inverse();
  return {Mi(0, 0), Mi(1, 1), Mi(2, 2)};
}

}  // namespace dembridge::torsion
