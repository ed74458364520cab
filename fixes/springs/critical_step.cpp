#include "critical_step.h"
#include "critical_parmec_order.h"

#include <Eigen/Dense>
#include <cfloat>
#include <cmath>

namespace dembridge::springs {

CriticalEstimate oscillator_step(double omega, double xi) {
  if (omega == 0.0) return {1.0, omega, xi};
  return {(2.0 / omega) * (std::sqrt(1.0 + xi * xi) - xi), omega, xi};
}

CriticalEstimate spring_critical(const SpringLaw& law, double m_s, bool parmec_order) {
  const double k = law.spring->max_abs_slope();
  const double omega = std::sqrt(k / m_s);
  double xi = 0.0;
  if (law.ratio_dashpot())
    xi = law.damping_ratio;
  else if (law.dashpot && omega > 0.0)
    xi = law.dashpot->max_abs_slope() / (2.0 * m_s * omega);
  return parmec_order ? parmec_order::oscillator_step(omega, xi) : oscillator_step(omega, xi);
}

double spring_max_damping(const SpringLaw& law, double m_s) {
  if (law.ratio_dashpot()) return law.damping_ratio * 2.0 * std::sqrt(law.spring->max_abs_slope() * m_s);
  if (law.dashpot) return law.dashpot->max_abs_slope();
  return 0.0;
}

void ParticleCritical::add_spring(double k_s, double e, const Vec3& d, bool planar, const Vec3& A) {
  ++count_;
  const double dl = norm(d);
  if (parmec_) {
    const Vec3 n = dl == 0.0 ? Vec3{1.0, 1.0, 1.0} : planar ? parmec_order::planar_counts(d)
                                                             : Vec3{std::fabs(d[0]), std::fabs(d[1]), std::fabs(d[2])};
    for (int i = 0; i < 3; ++i) axis_count_[i] += n[i];
    k_max_ = std::fmax(k_max_, k_s);
    e_max_ = std::fmax(e_max_, e);
    parmec_order::add_arm(krot_, A);
    return;
  }
  if (dl == 0.0) {
    axis_count_ = axis_count_ + Vec3{1.0, 1.0, 1.0};
  } else if (planar) {
    // two unit vectors spanning the plane normal to d: e1 = d x (least-aligned axis), e2 = n x e1
    const Vec3 n{d[0] / dl, d[1] / dl, d[2] / dl};
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (std::fabs(n[i]) < std::fabs(n[k])) k = i;
    Vec3 ax{};
    ax[k] = 1.0;
    Vec3 e1 = cross(n, ax);
    e1 = (1.0 / norm(e1)) * e1;
    const Vec3 e2 = cross(n, e1);
    for (int i = 0; i < 3; ++i) axis_count_[i] += std::fabs(e1[i]) + std::fabs(e2[i]);
  } else {
    for (int i = 0; i < 3; ++i) axis_count_[i] += std::fabs(d[i]);
  }
  k_max_ = std::fmax(k_max_, k_s);
  e_max_ = std::fmax(e_max_, e);
  const double a2 = dot(A, A);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) arm_sum_[3 * i + j] += (i == j ? a2 : 0.0) - A[i] * A[j];
}

CriticalEstimate ParticleCritical::estimate(double mass, const std::array<double, 9>& inertia) const {
  if (count_ == 0) return {DBL_MAX, 0.0, 0.0};
  if (parmec_) return parmec_order::particle_step(mass, inertia, axis_count_, k_max_, e_max_, krot_);
  const double nmax = std::fmax(axis_count_[0], std::fmax(axis_count_[1], axis_count_[2]));
  const double wt = std::sqrt(nmax * k_max_ / mass);
  CriticalEstimate best = oscillator_step(wt, wt > 0.0 ? e_max_ / (2.0 * mass * wt) : 0.0);
  using RowMat = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  const Eigen::Matrix3d K = k_max_ * Eigen::Map<const RowMat>(arm_sum_.data());
  const Eigen::Matrix3d J = Eigen::Map<const RowMat>(inertia.data());
  // omega_r^2 = lambda_max(L^-1 K L^-T), J = L L^T: the generalised problem K x = lambda J x
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix3d> ges(K, J, Eigen::EigenvaluesOnly);
  const double lmax = ges.eigenvalues()(2);
  if (lmax > 0.0) {
    const double jmin = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(J, Eigen::EigenvaluesOnly).eigenvalues()(0);
    const double wr = std::sqrt(lmax);
    const CriticalEstimate rot = oscillator_step(wr, e_max_ / (2.0 * jmin * wr));
    if (rot.step < best.step) best = rot;
  }
  return best;
}

}  // namespace dembridge::springs
