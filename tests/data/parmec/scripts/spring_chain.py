# Parmec-language script of the oracle cases 'spring_chain' (Parmec tests/spring_chain.py: ten unit cubes
# along the diagonal, cube i spans [i, i+1]^3, follower springs with dashpot tables between neighbours at
# (i, i, i), the last cube hung from the point (10, 10, 10)) and 'spring_chain_critical' (critical damping
# ratios 1/sqrt(2) between cubes and 0.5 at the top). ARGV: [step, duration, 'tables' | 'ratios'].
import math
args = ARGV ()
ratios = len (args) > 2 and args[2] == 'ratios'
matnum = MATERIAL (1E3, 1E9, 0.25)
spring = [-1, -1E7, 1, 1E7]
H = {'TIME': HISTORY ('TIME')}
prev = -1
for i in range (10):
  nodes = [i, i, i, i+1, i, i, i+1, i+1, i, i, i+1, i, i, i, i+1, i+1, i, i+1, i+1, i+1, i+1, i, i+1, i+1]
  p = MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum], matnum, 1)
  if prev >= 0:
    SPRING (p, (i, i, i), prev, (i, i, i), spring, 1 / math.sqrt (2) if ratios else [-1, -8E5, 1, 8E5])
  for e in ('PX', 'PY', 'PZ', 'VZ', 'OX', 'OY', 'OZ'):
    H['p%d_%s' % (p, e)] = HISTORY (e, p)
  prev = p
SPRING (p, (10, 10, 10), -1, (10, 10, 10), spring, 0.5 if ratios else [-1, -8E5, 1, 8E5])
for k in range (10):
  for e in ('LENGTH', 'STROKE', 'F', 'SF'):
    H['spr%d_%s' % (k, e)] = HISTORY (e, k)
GRAVITY (0., 0., -10.)
h = float (args[0]) if args else 0.25 * CRITICAL ()
DEM (float (args[1]) if len (args) > 1 else 5.0, h, (0.05, 10 * h))
