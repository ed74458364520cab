// The sphere half steps of fix nve/sphere (sphere_verlet_kernel.h): one atom against the closed form, and the
// AVX2 loop bitwise equal to the atom-by-atom loop on random atoms with a scattered group (blocks of four
// atoms all inside it, partly inside, and the 1-3 atoms after the last block).
#include "sphere_verlet_kernel.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

using namespace dembridge::integrate;

namespace {

struct Atoms {
  std::vector<double> x, v, omega, f, torque, radius, rmass;
  std::vector<int> mask;
  explicit Atoms(int n, unsigned seed) : x(3 * n), v(3 * n), omega(3 * n), f(3 * n), torque(3 * n), radius(n), rmass(n), mask(n)
  {
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.2, 2.0);
    for (auto *a : {&x, &v, &omega, &f, &torque})
      for (double &e : *a) e = u(g);
    for (int i = 0; i < n; i++) {
      radius[i] = pos(g);
      rmass[i] = pos(g);
      mask[i] = 1 | ((g() % 10 < 7) ? 4 : 0);  // about 70 % in group bit 4
    }
  }
  SphereArrays arrays() { return {x.data(), v.data(), omega.data(), f.data(), torque.data(), radius.data(), rmass.data(), mask.data()}; }
};

bool same_bits(const std::vector<double> &a, const std::vector<double> &b)
{
  // empty vectors may hold null data(), which memcmp must not get even for 0 bytes
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

}  // namespace

TEST(SphereVerlet, OneAtomClosedForm)
{
  Atoms a(1, 1);
  a.x = {1, 2, 3}, a.v = {0.5, -1, 2}, a.f = {4, 8, -2}, a.omega = {1, 0, -1}, a.torque = {0.2, 0.4, 0.8};
  a.radius = {0.5}, a.rmass = {2.0}, a.mask = {4};
  const SphereStep s{0.125, 0.0625, 0.125};  // dt, dt/2, dt/2 / inertia prefactor (0.5): exact in binary
  sphere_step<true>(a.arrays(), s, 1, 4, false);
  // v += dtf f / m = f / 32; x += dt v; omega += dtfrotate / (m r^2) torque = torque / 4
  EXPECT_EQ(a.v, (std::vector<double>{0.625, -0.75, 1.9375}));
  EXPECT_EQ(a.x, (std::vector<double>{1.078125, 1.90625, 3.2421875}));
  EXPECT_EQ(a.omega, (std::vector<double>{1 + 0.25 * 0.2, 0.25 * 0.4, -1 + 0.25 * 0.8}));
  sphere_step<false>(a.arrays(), s, 1, 2, false);  // not in group 2: unchanged
  EXPECT_EQ(a.omega, (std::vector<double>{1 + 0.25 * 0.2, 0.25 * 0.4, -1 + 0.25 * 0.8}));
}

TEST(SphereVerlet, Avx2EqualsScalarBitwise)
{
#if defined(__x86_64__)
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2: only the scalar loop runs";
  for (int n : {0, 3, 4, 7, 8, 1001}) {
    Atoms scalar(n, 7 + n), avx2(n, 7 + n);
    const SphereStep s{1e-4, 0.5e-4, 0.5e-4 / 0.4};
    for (int half = 0; half < 4; half++) {
      if (half % 2 == 0) {
        sphere_step<true>(scalar.arrays(), s, n, 4, false);
        sphere_step<true>(avx2.arrays(), s, n, 4, true);
      } else {
        sphere_step<false>(scalar.arrays(), s, n, 4, false);
        sphere_step<false>(avx2.arrays(), s, n, 4, true);
      }
    }
    EXPECT_TRUE(same_bits(scalar.x, avx2.x) && same_bits(scalar.v, avx2.v) && same_bits(scalar.omega, avx2.omega)) << "n = " << n;
    Atoms start(n, 7 + n);
    if (n > 8) {
      EXPECT_FALSE(same_bits(start.v, scalar.v));  // the steps did move the atoms
    }
  }
#else
  GTEST_SKIP() << "not an x86-64 build: there is no AVX2 loop";
#endif
}

