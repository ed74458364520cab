# Parmec-language script of the oracle case 'analytic_linear_spring': point mass m = 2 at the origin on a
# CONSTANT-direction spring k = 100 to space, v0 = 1; ARGV()[0] selects 'ratio', 'table' or 'undamped'.
import math
case = ARGV()[0]
m, k, zeta = 2.0, 100.0, 0.1
c = zeta * 2.0 * math.sqrt(k * m)
p = ANALYTICAL (mass = m)
VELOCITY (p, (1, 0, 0))
dashpot = {'ratio': zeta, 'table': [-1, -c, 1, c], 'undamped': None}[case]
s = SPRING (p, (0, 0, 0), -1, (0, 0, 0), [-1, -k, 1, k], dashpot, direction = (1, 0, 0))
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'VX', 'FX'):
  H[e] = HISTORY (e, p)
for e in ('LENGTH', 'STROKE', 'F', 'SF'):
  H['spr0_' + e] = HISTORY (e, s)
DEM (1.0, 0.001)
