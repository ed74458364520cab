#include "critical_parmec_order.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace dembridge::springs::parmec_order {

namespace {

// Parmec's literals as ISPC reads them: single precision (ALG_PI / 3.0 and 2*ALG_PI/3 are float operations)
const float kPi = static_cast<float>(3.14159265358979323846);
const double kPiThird = static_cast<double>(kPi / 3.0f);
const double kTwoPiThird = static_cast<double>((2.0f * kPi) / 3.0f);
const double kHalfPi = static_cast<double>(kPi) / 2.0;  // ISPC's double acos: π/2 - asin with that π

double fused3(double a0, double b0, double a1, double b1, double a2, double b2) {
  return dot_fused(Vec3{a0, a1, a2}, Vec3{b0, b1, b2});
}

// a*b - c*d as the build contracts it: fma(a, b, -(c*d))
double fused_diff(double a, double b, double c, double d) { return std::fma(a, b, -(c * d)); }

using Mat = std::array<double, 9>;  // column-major, as Parmec stores matrices

// C = A B (NNMUL), C = A Bᵀ (NTMUL): each entry a 3-term sum contracted as fused3
Mat multiply(const Mat& A, const Mat& B, bool transpose_b) {
  Mat C{};
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) {
      const double b0 = transpose_b ? B[col] : B[3 * col], b1 = transpose_b ? B[3 + col] : B[3 * col + 1],
                   b2 = transpose_b ? B[6 + col] : B[3 * col + 2];
      C[3 * col + row] = fused3(A[row], b0, A[3 + row], b1, A[6 + row], b2);
    }
  return C;
}

// Parmec's INVERT: cofactors times 1/det, the determinant expanded down the first column
Mat invert(const Mat& F) {
  const double c0 = fused_diff(F[4], F[8], F[5], F[7]), c1 = fused_diff(F[2], F[7], F[1], F[8]),
               c2 = fused_diff(F[1], F[5], F[2], F[4]);
  const double d = 1.0 / std::fma(c2, F[6], std::fma(F[0], c0, F[3] * c1));
  return {c0 * d, c1 * d, c2 * d, fused_diff(F[5], F[6], F[3], F[8]) * d, fused_diff(F[0], F[8], F[2], F[6]) * d,
          fused_diff(F[2], F[3], F[0], F[5]) * d, fused_diff(F[3], F[7], F[4], F[6]) * d,
          fused_diff(F[1], F[6], F[0], F[7]) * d, fused_diff(F[0], F[4], F[1], F[3]) * d};
}

}  // namespace

std::array<double, 9> inverse(const std::array<double, 9>& F) { return invert(F); }

double extremum_eigenvalue(const std::array<double, 9>& A, bool minimum) {
  const double p1 = fused3(A[3], A[3], A[6], A[6], A[7], A[7]);
  if (p1 == 0.0) return std::max(std::max(A[0], A[4]), A[8]);
  const double q = ((A[0] + A[4]) + A[8]) / 3.0;
  const double t0 = A[0] - q, t1 = A[4] - q, t2 = A[8] - q;
  const double p2 = std::fma(t2, t2, std::fma(t0, t0, t1 * t1)) + (p1 + p1);
  const double p = std::sqrt(p2 / 6.0);
  const double ip = 1.0 / p;
  const Mat B = {ip * t0, ip * A[1], ip * A[2], ip * A[3], ip * t1, ip * A[5], ip * A[6], ip * A[7], ip * t2};
  const double det = std::fma(B[6], fused_diff(B[1], B[5], B[2], B[4]),
                              std::fma(B[0], fused_diff(B[4], B[8], B[5], B[7]), B[3] * fused_diff(B[2], B[7], B[1], B[8])));
  const double r = 0.5 * det;
  double phi;
  if (r <= -1.0)
    phi = kPiThird;
  else if (r >= 1.0)
    phi = 0.0;
  else
    phi = (kHalfPi - std::asin(r)) / 3.0;
  return std::fma(2.0 * p, std::cos(minimum ? phi + kTwoPiThird : phi), q);
}

CriticalEstimate oscillator_step(double omega, double xi) {
  if (omega == 0.0) return {1.0, omega, xi};
  return {(2.0 / omega) * (std::sqrt(std::fma(xi, xi, 1.0)) - xi), omega, xi};
}

void add_arm(std::array<double, 6>& krot, const Vec3& A) {
  const double d = dot_fused(A, A);
  krot[0] += std::fma(-A[0], A[0], d);
  krot[1] += std::fma(-A[1], A[1], d);
  krot[2] += std::fma(-A[2], A[2], d);
  krot[3] = std::fma(-A[0], A[1], krot[3]);
  krot[4] = std::fma(-A[0], A[2], krot[4]);
  krot[5] = std::fma(-A[1], A[2], krot[5]);
}

Vec3 planar_counts(const Vec3& d) {
  Vec3 t1{d[0] + 0.123f, d[1] + 0.346f, d[2] + 0.789f};  // float literals, as ISPC reads them
  Vec3 t2 = cross_fused(d, t1);
  const double i2 = 1.0 / std::sqrt(dot_fused(t2, t2));
  t2 = {t2[0] * i2, t2[1] * i2, t2[2] * i2};
  t1 = cross_fused(t2, d);
  return {std::fabs(t1[0]) + std::fabs(t2[0]), std::fabs(t1[1]) + std::fabs(t2[1]), std::fabs(t1[2]) + std::fabs(t2[2])};
}

CriticalEstimate particle_step(double mass, const std::array<double, 9>& J, const Vec3& kact, double k, double e,
                               const std::array<double, 6>& krot) {
  const double n = std::max(std::max(kact[0], kact[1]), kact[2]);
  if (!(n > 0.0)) return {DBL_MAX, 0.0, 0.0};
  const double w_xyz = std::sqrt(n * k / mass);
  const double xi_xyz = e / (2.0 * mass * w_xyz);
  const double h_xyz = (2.0 / w_xyz) * (std::sqrt(std::fma(xi_xyz, xi_xyz, 1.0)) - xi_xyz);
  const Mat K = {k * krot[0], k * krot[3], k * krot[4], k * krot[3], k * krot[1], k * krot[5],
                 k * krot[4], k * krot[5], k * krot[2]};
  if (K[0] == 0.0 && K[4] == 0.0 && K[8] == 0.0) return {h_xyz, w_xyz, xi_xyz};  // Q21 fixed
  const double m_rot = extremum_eigenvalue(J, true);
  // Cholesky J = L Lᵀ (column-major L), A = L⁻¹ K L⁻ᵀ
  Mat L{};
  L[0] = std::sqrt(J[0]);
  double inv = 1.0 / L[0];
  L[1] = inv * J[1];
  L[2] = inv * J[2];
  L[4] = std::sqrt(std::fma(-L[1], L[1], J[4]));
  inv = 1.0 / L[4];
  L[5] = inv * std::fma(-L[2], L[1], J[5]);
  L[8] = std::sqrt(J[8] - std::fma(L[2], L[2], L[5] * L[5]));
  const Mat Li = invert(L);
  const double w_rot = std::sqrt(extremum_eigenvalue(multiply(Li, multiply(K, Li, true), false), false));
  const double xi_rot = e / (2.0 * m_rot * w_rot);
  const double h_rot = (2.0 / w_rot) * (std::sqrt(std::fma(xi_rot, xi_rot, 1.0)) - xi_rot);
  return {std::min(h_xyz, h_rot), std::max(w_xyz, w_rot), std::max(xi_xyz, xi_rot)};
}

}  // namespace dembridge::springs::parmec_order
