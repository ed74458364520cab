# Two non-cubic MESH boxes: A (0.5 x 0.5 x 2, pinned in space at its top) and B (1.0 x 0.4 x 0.6) hanging from
# A by a BALL_JOINT; a TORSION_SPRING between them with spring tables on every axis and critical-ratio dampers.
# B starts spinning about a tilted axis (its centre velocity matching the joint). HISTORY: the torsion spring
# (angles, torques, frame), both bodies' spatial angular velocities and material points at the centre and one
# unit away along each axis (the rotation of A is read from them). ARGV: [step, duration, JSON file for H].
step = float (ARGV()[0])
duration = float (ARGV()[1])
mat = MATERIAL (1E3, 1E9, 0.25)

def box (lo, size):
  x0, y0, z0 = lo
  a, b, c = size
  nodes = [x0, y0, z0, x0+a, y0, z0, x0+a, y0+b, z0, x0, y0+b, z0,
           x0, y0, z0+c, x0+a, y0, z0+c, x0+a, y0+b, z0+c, x0, y0+b, z0+c]
  return MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, mat], mat, 1)

A = box ((-0.25, -0.25, 0.0), (0.5, 0.5, 2.0))   # centre (0, 0, 1)
B = box ((-0.5, -0.2, -0.6), (1.0, 0.4, 0.6))    # centre (0, 0, -0.3)
BALL_JOINT (A, (0.0, 0.0, 2.0))
BALL_JOINT (A, (0.0, 0.0, 0.0), B)
w = (0.6, 0.9, 2.0)
VELOCITY (B, linear = (w[1]*(-0.3), -w[0]*(-0.3), 0.0), angular = w)   # w x (centre - joint point)
GRAVITY (0.0, 0.0, -10.0)
t = TORSION_SPRING (A, B, (0, 0, 1), (1, 0, 0), kroll = [-1, 3000, 1, -3000], kpitch = [-1, 2000, 1, -2000],
                    kyaw = [-1, 500, 1, -500], droll = 0.2, dpitch = 0.3, dyaw = 0.5)
H = {'TIME': HISTORY ('TIME')}
for e in ('ROLL', 'PITCH', 'YAW', 'TRQTOT_R', 'TRQTOT_P', 'TRQTOT_Y', 'TRQSPR_R', 'TRQSPR_P', 'TRQSPR_Y',
          'XDIR_X', 'XDIR_Y', 'XDIR_Z', 'ZDIR_X', 'ZDIR_Y', 'ZDIR_Z'):
  H['trq0_' + e] = HISTORY (e, t)
for name, p, X in (('A', A, (0.0, 0.0, 1.0)), ('B', B, (0.0, 0.0, -0.3))):
  for e in ('OX', 'OY', 'OZ'):
    H[name + '_' + e] = HISTORY (e, p)
  for k, P in enumerate ((X, (X[0]+1, X[1], X[2]), (X[0], X[1]+1, X[2]), (X[0], X[1], X[2]+1))):
    for e in ('PX', 'PY', 'PZ'):
      H['%s%d_%s' % (name, k, e)] = HISTORY (e, p, point = P)
DEM (duration, step)
import json
json.dump (H, open (ARGV()[2], 'w'))
