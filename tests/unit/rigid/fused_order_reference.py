#!/usr/bin/env python3
"""Expected values of tests/unit/rigid/test_fused_order.cpp, computed independently of fixes/rigid: every
fused multiply-add as the exactly rounded Fraction a*b + c (float(Fraction) rounds to nearest even), every
plain product or sum as Python's IEEE double operation.

The case: one float_taylor rotation_step with L = I, W = 0 (so exp(-h/2 W) = I and B = h/2 T exactly),
J a full symmetric tensor, Jinv its exact inverse rounded, torque (1, 3, 2), h = 1. Then
  A  = Jinv B        (row sums fused middle product first: fma(a2, b2, fma(a1, b1, a0 b0)))
  c  = A x (J A)     (J A fused first: fma(a2, b2, fma(a0, b0, a1 b1)); cross_fused)
  W' = Jinv (h (T - c))   (fused first)
Printed: Jinv, W' with A fused middle first (what Parmec's build does) and W' with A fused first (the
order of every other product sum); they differ in the last bit of W'x.

usage: python3 tests/unit/rigid/fused_order_reference.py
"""
from fractions import Fraction as F

J = [[2.0, 0.3, 0.1], [0.3, 3.0, 0.2], [0.1, 0.2, 4.0]]
TORQUE = [1.0, 3.0, 2.0]
H = 1.0


def fma(a, b, c):
    return float(F(a) * F(b) + F(c))


def fused_first(a, b):
    return fma(a[2], b[2], fma(a[0], b[0], a[1] * b[1]))


def fused_middle(a, b):
    return fma(a[2], b[2], fma(a[1], b[1], a[0] * b[0]))


def inverse(m):
    (a, b, c), (d, e, f), (g, h, i) = [[F(x) for x in r] for r in m]
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    adj = [[e * i - f * h, c * h - b * i, b * f - c * e], [f * g - d * i, a * i - c * g, c * d - a * f],
           [d * h - e * g, b * g - a * h, a * e - b * d]]
    return [[float(x / det) for x in r] for r in adj]


def new_omega(jinv, a_row):
    b = [fma(0.5 * H, t, 0.0) for t in TORQUE]
    a = [a_row(jinv[i], b) for i in range(3)]
    ja = [fused_first(J[i], a) for i in range(3)]
    c = [fma(a[1], ja[2], -(a[2] * ja[1])), fma(a[2], ja[0], -(a[0] * ja[2])), fma(a[0], ja[1], -(a[1] * ja[0]))]
    ht = [H * (TORQUE[i] - c[i]) for i in range(3)]
    return [fused_first(jinv[i], ht) for i in range(3)]


if __name__ == "__main__":
    jinv = inverse(J)
    print("Jinv", [[x.hex() for x in r] for r in jinv])
    print("W' (A fused middle first)", [w.hex() for w in new_omega(jinv, fused_middle)])
    print("W' (A fused first)       ", [w.hex() for w in new_omega(jinv, fused_first)])
