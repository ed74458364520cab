#include "BodyRotation.h"

#include <cmath>

namespace dembridge::rigid {

Mat3 expmap(const Vec3 &theta, bool q3_typo)
{
  const double o1 = theta[0], o2 = theta[1], o3 = theta[2];
  const double v0 = o1 * o1, v1 = o2 * o2, v2 = o3 * o3;
  const double a = v0 + v1 + v2;
  double sx, cx;
  if (a < 3.0461741978671E-02) {
    // Taylor series of sin(r)/r and (1 − cos r)/r² in a = r² (Parmec's coefficients, spec §1.2)
    sx = 1.0 + (-1.666666666666667E-1 +
                (8.333333333333333E-3 +
                 (-1.984126984126984E-4 + (2.755731922398589E-6 + (-2.505210838544172E-8 + 1.605904383682161E-10 * a) * a) * a) *
                     a) *
                    a) *
                   a;
    cx = 0.5 + (-4.166666666666667E-2 +
                (1.388888888888889E-3 +
                 (-2.480158730158730E-5 + (2.755731922398589E-7 + (-2.087675698786810E-9 + 1.147074559772972E-11 * a) * a) * a) *
                     a) *
                    a) *
                   a;
  } else {
    const double r = std::sqrt(a);
    sx = std::sin(r) / r;
    cx = (1.0 - std::cos(r)) / a;
  }
  const double v01 = o1 * o2, v12 = o2 * o3;
  const double v02 = q3_typo ? o2 * o3 : o1 * o3;
  const double s0 = sx * o1, s1 = sx * o2, s2 = sx * o3;
  Mat3 L;
  L << 1.0 - cx * (v2 + v1), cx * v01 - s2, cx * v02 + s1,  //
      cx * v01 + s2, 1.0 - cx * (v2 + v0), cx * v12 - s0,   //
      cx * v02 - s1, cx * v12 + s0, 1.0 - cx * (v1 + v0);
  return L;
}

Mat3 inertia_from_list(const double *s)
{
  Mat3 J;
  J << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
  return J;
}

RotationStep rotation_step(const Mat3 &J, const Mat3 &Jinv, const Mat3 &L, const Vec3 &W, const Vec3 &torque,
                           double h, bool q3_typo)
{
  const Vec3 T = L.transpose() * torque;
  const Vec3 B = expmap(-0.5 * h * W, q3_typo) * (J * W) + 0.5 * h * T;
  const Vec3 A = Jinv * B;
  const Vec3 dO = Jinv * (h * (T - A.cross(J * A)));
  RotationStep out;
  out.W = W + dO;
  out.L = L * expmap(h * out.W, q3_typo);
  out.w = out.L * out.W;
  return out;
}

int orthonormalise(const double *dirs, int ndirs, Vec3 out[3])
{
  int n = 0;
  for (int k = 0; k < ndirs && n < 3; k++) {
    Vec3 d(dirs[3 * k], dirs[3 * k + 1], dirs[3 * k + 2]);
    for (int j = 0; j < n; j++) d -= d.dot(out[j]) * out[j];
    const double len = d.norm();
    if (len > 1e-12) out[n++] = d / len;
  }
  return n;
}

Vec3 remove_components(const Vec3 &v, const Vec3 basis[3], int n)
{
  Vec3 r = v;
  for (int k = 0; k < n; k++) r -= v.dot(basis[k]) * basis[k];
  return r;
}

}  // namespace dembridge::rigid
