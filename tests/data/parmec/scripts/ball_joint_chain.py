# Parmec-language script of the oracle case 'ball_joint_chain' (Parmec tests/ball_joint_chain.py with ten
# cubes): cube i spans [i, i+1]^3, consecutive cubes joined by BALL_JOINTs at (i, i, i), the last cube pinned
# at (10, 10, 10); gravity -10 z. ARGV()[0] = duration (default 10 s), ARGV()[1] = step (default 0.001).
matnum = MATERIAL (1E3, 1E9, 0.25)
H = {'TIME': HISTORY ('TIME')}
prevpar = -1
points = []
for i in range (0, 10):
  nodes = [i, i, i, i+1, i, i, i+1, i+1, i, i, i+1, i,
           i, i, i+1, i+1, i, i+1, i+1, i+1, i+1, i, i+1, i+1]
  elements = [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum]
  colors = [1, 4, 0, 1, 2, 3, 2, 4, 4, 5, 6, 7, 3]
  parnum = MESH (nodes, elements, matnum, colors)
  for e in ('PX', 'PY', 'PZ', 'OX', 'OY', 'OZ'):
    H['p%d_%s' % (parnum, e)] = HISTORY (e, parnum)
  if i:
    j = BALL_JOINT (parnum, (i, i, i), prevpar)
    points.append ((j, (i, i, i), parnum, prevpar))
  prevpar = parnum
j = BALL_JOINT (parnum, (i+1, i+1, i+1))
for j in range (10):
  for e in ('JREAC_X', 'JREAC_Y', 'JREAC_Z', '|JREAC|'):
    H['j%d_%s' % (j, e)] = HISTORY (e, j)
for j, pt, a, b in points:
  for e in ('PX', 'PY', 'PZ'):
    H['jpt%d_on_p%d_%s' % (j, a, e)] = HISTORY (e, a, point = pt)
    H['jpt%d_on_p%d_%s' % (j, b, e)] = HISTORY (e, b, point = pt)
GRAVITY (0., 0., -10.)
duration = float (ARGV()[0]) if ARGV() else 10.0
h = float (ARGV()[1]) if len (ARGV()) > 1 else 0.001
DEM (duration, h, (0.05, 0.01))
