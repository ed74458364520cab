#include "body_rotation.h"

#include "math/inertia.h"

#include <array>
#include <cmath>

namespace dembridge::rigid {

namespace {
// Taylor coefficients of sin(r)/r and (1 − cos r)/r² in a = r², and the threshold (Parmec's, spec §1.2)
constexpr double kThreshold = 3.0461741978671E-02;
constexpr double kSin[7] = {1.0, -1.666666666666667E-1, 8.333333333333333E-3, -1.984126984126984E-4,
                            2.755731922398589E-6, -2.505210838544172E-8, 1.605904383682161E-10};
constexpr double kCos[7] = {0.5, -4.166666666666667E-2, 1.388888888888889E-3, -2.480158730158730E-5,
                            2.755731922398589E-7, -2.087675698786810E-9, 1.147074559772972E-11};

double coefficient(double c, bool single) { return single ? double(float(c)) : c; }

// c0 + (c1 + (c2 + ... + c6 a) a ...) a, Horner from the inside as Parmec writes it
double series(const double *c, double a, bool single)
{
  if (single) {  // ISPC: every step c_k + t a contracted to fma(t, a, c_k)
    double t = std::fma(coefficient(c[6], true), a, coefficient(c[5], true));
    for (int k = 4; k >= 0; k--) t = std::fma(t, a, coefficient(c[k], true));
    return t;
  }
  double s = coefficient(c[6], single) * a;
  for (int k = 5; k >= 1; k--) s = (coefficient(c[k], single) + s) * a;
  return coefficient(c[0], single) + s;
}

// Products as Parmec's ISPC build rounds them (Q27): a row sum A(r,0) b0 + A(r,1) b1 + A(r,2) b2 is
// fma(A(r,2), b2, fma(A(r,0), b0, A(r,1) b1)).
double row_fused(double a0, double a1, double a2, double b0, double b1, double b2)
{
  return std::fma(a2, b2, std::fma(a0, b0, a1 * b1));
}
// The same sum with the middle product fused first: fma(a2, b2, fma(a1, b1, a0 b0)). Which of the first two
// products LLVM contracts depends on the operand order its passes leave in that add, not on the source order;
// matched step by step against the oracle (a replay of the hung cube's 2000 steps with Parmec's recorded torques
// reproduces every ω bit only with this order in J⁻¹ B and in the middle column of Λ exp(hΩ)).
double row_fused_middle(double a0, double a1, double a2, double b0, double b1, double b2)
{
  return std::fma(a2, b2, std::fma(a1, b1, a0 * b0));
}
// A b with each row summed by Row (row_fused or row_fused_middle)
template <double (*Row)(double, double, double, double, double, double)>
Vec3 mul_rows(const Mat3 &A, const Vec3 &b)
{
  Vec3 r;
  for (int i = 0; i < 3; i++) r[i] = Row(A(i, 0), A(i, 1), A(i, 2), b[0], b[1], b[2]);
  return r;
}
// Λ exp(hΩ) as dynamics.ispc's build rounds it: columns 0 and 2 row_fused, column 1 row_fused_middle
Mat3 mul_rotation_fused(const Mat3 &A, const Mat3 &B)
{
  Mat3 C;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      C(i, j) = (j == 1 ? row_fused_middle : row_fused)(A(i, 0), A(i, 1), A(i, 2), B(0, j), B(1, j), B(2, j));
  return C;
}
Vec3 tmul_fused(const Mat3 &A, const Vec3 &b)  // Aᵀ b
{
  Vec3 r;
  for (int i = 0; i < 3; i++) r[i] = row_fused(A(0, i), A(1, i), A(2, i), b[0], b[1], b[2]);
  return r;
}
Vec3 cross_fused(const Vec3 &a, const Vec3 &b)  // math::cross_fused on Eigen vectors
{
  const math::Vec3 c = math::cross_fused({a[0], a[1], a[2]}, {b[0], b[1], b[2]});
  return Vec3(c[0], c[1], c[2]);
}
}  // namespace

Mat3 macro_mul(const Mat3 &A, const Mat3 &B)
{
  Mat3 C;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) C(i, j) = A(i, 0) * B(0, j) + A(i, 1) * B(1, j) + A(i, 2) * B(2, j);
  return C;
}

Mat3 macro_mul_t(const Mat3 &A, const Mat3 &B)
{
  Mat3 C;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) C(i, j) = A(i, 0) * B(j, 0) + A(i, 1) * B(j, 1) + A(i, 2) * B(j, 2);
  return C;
}

Vec3 macro_mv(const Mat3 &A, const Vec3 &b)
{
  Vec3 r;
  for (int i = 0; i < 3; i++) r[i] = A(i, 0) * b[0] + A(i, 1) * b[1] + A(i, 2) * b[2];
  return r;
}

Vec3 macro_tmv(const Mat3 &A, const Vec3 &b)
{
  Vec3 r;
  for (int i = 0; i < 3; i++) r[i] = A(0, i) * b[0] + A(1, i) * b[1] + A(2, i) * b[2];
  return r;
}

Mat3 expmap(const Vec3 &theta, bool q3_typo, bool float_taylor)
{
  const double o1 = theta[0], o2 = theta[1], o3 = theta[2];
  const double v0 = o1 * o1, v1 = o2 * o2, v2 = o3 * o3;
  const double a = v0 + v1 + v2;
  double sx, cx;
  if (a < coefficient(kThreshold, float_taylor)) {
    sx = series(kSin, a, float_taylor);
    cx = series(kCos, a, float_taylor);
  } else {
    const double r = std::sqrt(a);
    sx = std::sin(r) / r;
    cx = (1.0 - std::cos(r)) / a;
  }
  const double v01 = o1 * o2, v12 = o2 * o3;
  const double v02 = q3_typo ? o2 * o3 : o1 * o3;
  const double s0 = sx * o1, s1 = sx * o2, s2 = sx * o3;
  // ISPC contracts the diagonal −c s + 1 of the first two rows (the product has one use; the off-diagonal
  // products are shared), but not of the third, Lambda9 = −cx (v1 + v0) + 1. Fused, spring_chain_critical's
  // p1 gets Λ(3,3) one ulp below Parmec's at step 584 (the two roundings differ at 1 of its first 6 160 body
  // steps), which that chain amplifies to 3.2e-11; unfused every row of the recorded 10 s is bit for bit.
  // Which contraction LLVM makes is not visible in the source (see row_fused_middle); found by replaying the
  // dumped steps with each operation of the step rounded the other way (doc/parmec_front_end.md). The first
  // two entries are fused as the source suggests: no oracle case tells (unfused they change no row).
  const double d0 = float_taylor ? std::fma(-cx, v2 + v1, 1.0) : 1.0 - cx * (v2 + v1);
  const double d1 = float_taylor ? std::fma(-cx, v2 + v0, 1.0) : 1.0 - cx * (v2 + v0);
  const double d2 = 1.0 - cx * (v1 + v0);
  Mat3 L;
  L << d0, cx * v01 - s2, cx * v02 + s1,  //
      cx * v01 + s2, d1, cx * v12 - s0,   //
      cx * v02 - s1, cx * v12 + s0, d2;
  return L;
}

Mat3 to_mat3(const math::Mat9 &m)
{
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m.data());
}

math::Mat9 to_mat9(const Mat3 &m)
{
  math::Mat9 rows;
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(rows.data()) = m;
  return rows;
}

Mat3 parmec_inverse(const Mat3 &F) { return to_mat3(math::inverse_parmec(to_mat9(F))); }

RotationStep rotation_step(const Mat3 &J, const Mat3 &Jinv, const Mat3 &L, const Vec3 &W, const Vec3 &torque,
                           double h, bool q3_typo, bool float_taylor)
{
  if (float_taylor) {  // dynamics.ispc's operations, each product sum fused as its build does
    const double half = 0.5 * h;
    const Vec3 T = tmul_fused(L, torque);
    const Vec3 JW = mul_rows<row_fused>(J, W);
    Vec3 B = mul_rows<row_fused>(expmap(Vec3(-half * W[0], -half * W[1], -half * W[2]), q3_typo, true), JW);
    for (int c = 0; c < 3; c++) B[c] = std::fma(half, T[c], B[c]);
    const Vec3 A = mul_rows<row_fused_middle>(Jinv, B);
    const Vec3 c = cross_fused(A, mul_rows<row_fused>(J, A));
    const Vec3 hT(h * (T[0] - c[0]), h * (T[1] - c[1]), h * (T[2] - c[2]));
    RotationStep out;
    out.W = W + mul_rows<row_fused>(Jinv, hT);
    out.L = mul_rotation_fused(L, expmap(Vec3(h * out.W[0], h * out.W[1], h * out.W[2]), q3_typo, true));
    out.w = mul_rows<row_fused>(out.L, out.W);
    return out;
  }
  // joints.cpp's free step (C++, macro order)
  const Vec3 T = macro_tmv(L, torque);
  const Vec3 B = macro_mv(expmap(-0.5 * h * W, q3_typo, float_taylor), macro_mv(J, W)) + 0.5 * h * T;
  const Vec3 A = macro_mv(Jinv, B);
  const Vec3 dO = macro_mv(Jinv, h * (T - A.cross(macro_mv(J, A))));
  RotationStep out;
  out.W = W + dO;
  out.L = macro_mul(L, expmap(h * out.W, q3_typo, float_taylor));
  out.w = macro_mv(out.L, out.W);
  return out;
}

int orthonormalise(const double *dirs, int ndirs, Vec3 out[3])
{
  int n = 0;
  for (int k = 0; k < ndirs && n < 3; k++) {
    Vec3 d(dirs[3 * k], dirs[3 * k + 1], dirs[3 * k + 2]);
    for (int j = 0; j < n; j++) {
      const double dot = out[j].dot(d);  // Parmec: DOT(dir[j], dir[k]), then dir[k] -= dot dir[j]
      d -= dot * out[j];
    }
    const double len = std::sqrt(d.dot(d));
    if (len > 1e-12) out[n++] = Vec3(d[0] / len, d[1] / len, d[2] / len);
  }
  return n;
}

Vec3 remove_components(const Vec3 &v, const Vec3 basis[3], int n)
{
  Vec3 r = v;
  for (int k = 0; k < n; k++) {
    const double dot = r.dot(basis[k]);
    r -= dot * basis[k];
  }
  return r;
}

}  // namespace dembridge::rigid
