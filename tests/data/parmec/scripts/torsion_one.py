# Parmec-language script of the oracle cases 'torsion_spring_one/caseNN' (Parmec tests/torsion_spring_one.py:
# unit cube + TORSION_SPRING to space, initial spin) and 'analytic_torsion' (isotropic ANALYTICAL body,
# I = 2, tables k = 50 on every axis). ARGV: [JSON {"body": "cube"|"analytical", "args": TORSION_SPRING
# keyword arguments, "w0": initial spin, "duration": s}, step].
import json
spec = json.loads (ARGV()[0])
step = float (ARGV()[1])
if spec['body'] == 'cube':
  matnum = MATERIAL (1E3, 1E9, 0.25)
  nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]
  parnum = MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum], matnum, 1)
  args = spec['args']
else:
  parnum = ANALYTICAL ([2.0, 2.0, 2.0, 0.0, 0.0, 0.0], 1.0)
  k = [-1, 50.0, 1, -50.0]
  args = dict (zdir = (0, 0, 1), xdir = (1, 0, 0), kroll = k, kpitch = k, kyaw = k)
  args.update (spec['args'])
for key in ('zdir', 'xdir'):
  args[key] = tuple (args[key])
if 'cone' in args:
  args['cone'] = tuple (args['cone'])
t = TORSION_SPRING (parnum, -1, **args)
VELOCITY (parnum, angular = tuple (spec['w0']))
H = {'TIME': HISTORY ('TIME')}
for e in ('OX', 'OY', 'OZ', 'TX', 'TY', 'TZ', 'PX', 'PY', 'PZ'):
  H[e] = HISTORY (e, parnum)
for e in ('ROLL', 'PITCH', 'YAW', 'TRQTOT_R', 'TRQTOT_P', 'TRQTOT_Y', 'TRQSPR_R', 'TRQSPR_P', 'TRQSPR_Y'):
  H['trq0_' + e] = HISTORY (e, t)
DEM (spec['duration'], step)
