#include "equivalent_mass.h"
#include "critical_parmec_order.h"
#include "math/inertia.h"

#include <Eigen/Dense>
#include <stdexcept>

namespace dembridge::springs {

namespace {

using Mat3 = Eigen::Matrix3d;

Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0;
  return s;
}

Mat3 point_inverse_mass_matrix(const BodyMass& b, const Vec3& P, EqmArm arm) {
  const Vec3 point = arm == EqmArm::ParmecQ8 ? P - b.centre : P;  // Q8: the arm is passed where a point is expected
  const Vec3 A = b.centre - point;
  const Mat3 Jinv = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(b.inv_inertia.data());
  const Mat3 S = skew(A);
  return Mat3::Identity() / b.mass + S.transpose() * Jinv * S;
}

// Parmec's eqm() (parmec.ispc, compiled with contraction, quirk Q27): M⁻¹ = ([A]×ᵀ J⁻¹) [A]× with every
// 3-term sum contracted as dot_fused (spring_vec3.h), 1/m added to the diagonal afterwards; part2's matrix added.
double fused_sum(double a0, double b0, double a1, double b1, double a2, double b2) {
  return dot_fused(Vec3{a0, a1, a2}, Vec3{b0, b1, b2});
}

// ([A]×ᵀ J⁻¹) [A]× of one body, without the 1/m diagonal (eqm() adds it after summing the two bodies'
// matrices: M⁻¹ = (M1 + 1/m1) + M2, then + 1/m2).
Mat3 rotational_inverse_mass_fused(const BodyMass& b, const Vec3& P, EqmArm arm) {
  const Vec3 point = arm == EqmArm::ParmecQ8 ? P - b.centre : P;
  const Vec3 A = b.centre - point;
  const Mat3 S = skew(A);
  const Mat3 Jinv = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(b.inv_inertia.data());
  Mat3 T, M;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) T(i, j) = fused_sum(S(0, i), Jinv(0, j), S(1, i), Jinv(1, j), S(2, i), Jinv(2, j));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M(i, j) = fused_sum(T(i, 0), S(0, j), T(i, 1), S(1, j), T(i, 2), S(2, j));
  return M;
}

void add_inverse_mass(Mat3& M, const BodyMass& b) {
  const double im = 1.0 / b.mass;
  for (int i = 0; i < 3; ++i) M(i, i) += im;
}

}  // namespace

BodyMass BodyMass::isotropic(double mass, double inertia, const Vec3& centre) {
  BodyMass b;
  b.mass = mass;
  b.inv_inertia = {1.0 / inertia, 0.0, 0.0, 0.0, 1.0 / inertia, 0.0, 0.0, 0.0, 1.0 / inertia};
  b.centre = centre;
  return b;
}

BodyMass BodyMass::from_inertia_list(double mass, const double* six, const Vec3& centre) {
  BodyMass b;
  b.mass = mass;
  b.inv_inertia = math::inverse_parmec(math::inertia_from_list(six));
  b.centre = centre;
  return b;
}

std::array<double, 9> point_inverse_mass(const BodyMass& body, const Vec3& P, EqmArm arm) {
  const Mat3 m = point_inverse_mass_matrix(body, P, arm);
  std::array<double, 9> out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[3 * i + j] = m(i, j);
  return out;
}

double equivalent_mass(const BodyMass& body1, const Vec3& P1, const BodyMass* body2, const Vec3& P2, const Vec3& d,
                       EqmArm arm, bool fused, bool parmec_eigenvalue) {
  Mat3 Minv;
  if (fused) {  // eqm()'s order: ((M1 + 1/m1) + M2) + 1/m2
    Minv = rotational_inverse_mass_fused(body1, P1, arm);
    add_inverse_mass(Minv, body1);
    if (body2) {
      Minv += rotational_inverse_mass_fused(*body2, P2, arm);
      add_inverse_mass(Minv, *body2);
    }
  } else {
    Minv = point_inverse_mass_matrix(body1, P1, arm);
    if (body2) Minv += point_inverse_mass_matrix(*body2, P2, arm);
  }
  double lambda;
  if (fused && (d[0] != 0.0 || d[1] != 0.0 || d[2] != 0.0)) {  // NVMUL then DOT, contracted
    Vec3 t;
    for (int i = 0; i < 3; ++i) t[i] = fused_sum(Minv(i, 0), d[0], Minv(i, 1), d[1], Minv(i, 2), d[2]);
    lambda = fused_sum(t[0], d[0], t[1], d[1], t[2], d[2]);
  } else if (fused && parmec_eigenvalue && d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0) {
    std::array<double, 9> m;  // symmetric: row- and column-major alike
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[3 * j + i] = Minv(i, j);
    lambda = parmec_order::extremum_eigenvalue(m, true);
  } else if (d[0] != 0.0 || d[1] != 0.0 || d[2] != 0.0) {
    const Eigen::Vector3d v(d[0], d[1], d[2]);
    lambda = v.dot(Minv * v);
  } else {
    lambda = Eigen::SelfAdjointEigenSolver<Mat3>(Minv, Eigen::EigenvaluesOnly).eigenvalues()(0);
  }
  if (!(lambda > 0.0)) throw std::invalid_argument("EQM: the inverse mass matrix is not positive along the direction");
  return 1.0 / lambda;
}

}  // namespace dembridge::springs
