// The few operations a contact law written over its number type R needs beyond + - * / and
// comparisons: R is double (one contact) or Lanes4 (four contacts, one per lane; GCC vector
// extension). Every lane operation is the IEEE operation of the scalar code, so a lane's result is
// bit-identical to the scalar one (issue 12: the neighbour loop evaluates touching pairs four at a
// time). Branches become lane_select. The Lanes4 forms stay free of target attributes (sqrt as
// asm) so that a law compiled for the baseline target can be inlined into the
// AVX2-compiled loop (pair_gran_loop.h), where GCC then emits 256-bit instructions. Every function
// taking or returning Lanes4 by value must be always_inline: an out-of-line copy would be compiled
// for the baseline target, whose calling convention for 256-bit vectors differs (garbage lanes).
#pragma once

#include <algorithm>
#include <cmath>

namespace dembridge::gran {

inline double lane_sqrt(double x) { return std::sqrt(x); }
inline double lane_fabs(double x) { return std::fabs(x); }
inline double lane_min(double a, double b) { return std::min(a, b); }
inline double lane_select(bool c, double a, double b) { return c ? a : b; }
inline double lane_splat(double x, double) { return x; }
inline double lane_pow(double x, double y) { return std::pow(x, y); }

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#define DEMBRIDGE_HAVE_LANES4 1
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // Lanes4 by value: only ever inlined into AVX2 code
typedef double Lanes4 __attribute__((vector_size(32)));
typedef decltype(Lanes4{} < Lanes4{}) LaneMask4;  // what a lane comparison gives: -1 (true) or 0

// One 256-bit vsqrtpd (the correctly rounded root of each lane, as sqrtsd): written as asm because
// the AVX builtin is not declared outside AVX code; Lanes4 code only ever runs inlined into the AVX2
// loop. (Two SSE2 halves took six instructions per root.)
[[gnu::always_inline]] inline Lanes4 lane_sqrt(Lanes4 x)
{
  Lanes4 root;
  asm("vsqrtpd %1, %0" : "=x"(root) : "xm"(x));
  return root;
}
[[gnu::always_inline]] inline Lanes4 lane_fabs(Lanes4 x)
{
  return (Lanes4)((LaneMask4)x & (LaneMask4){0x7fffffffffffffff, 0x7fffffffffffffff, 0x7fffffffffffffff, 0x7fffffffffffffff});
}
[[gnu::always_inline]] inline Lanes4 lane_select(LaneMask4 c, Lanes4 a, Lanes4 b) { return c ? a : b; }
[[gnu::always_inline]] inline Lanes4 lane_min(Lanes4 a, Lanes4 b) { return lane_select(b < a, b, a); }  // std::min(a, b) per lane
[[gnu::always_inline]] inline Lanes4 lane_splat(double x, Lanes4) { return (Lanes4){x, x, x, x}; }
[[gnu::always_inline]] inline Lanes4 lane_pow(Lanes4 x, double y) { return (Lanes4){std::pow(x[0], y), std::pow(x[1], y), std::pow(x[2], y), std::pow(x[3], y)}; }
#pragma GCC diagnostic pop
#endif

}  // namespace dembridge::gran
