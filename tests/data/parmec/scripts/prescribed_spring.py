# Parmec-language script of the oracle cases 'analytic_ylim_cycle' (point mass at the origin) and
# 'spring_general' (Parmec tests/spring_general.py: unit cube): a CONSTANT-direction spring (direction x) with
# an unload curve and yield limits, its particle driven by a prescribed velocity TSERIES (vt, vx).
# ARGV: [JSON {"body": "point"|"cube", "spring", "unload", "ylim", "vt", "vx", "duration"}, step].
import json
m = json.loads (ARGV()[0])
step = float (ARGV()[1])
if m['body'] == 'point':
  p = ANALYTICAL (mass = 1.0)
  point = (0, 0, 0)
else:
  matnum = MATERIAL (1E3, 1E9, 0.25)
  nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]
  p = MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum], matnum, 1)
  point = (0.5, 0.5, 0.5)
sign = -1.0 if m['body'] == 'point' else 1.0  # stroke = -x for a spring to the particle, +x for one from it
if m['body'] == 'point':
  s = SPRING (p, point, -1, point, m['spring'], direction = (1, 0, 0), unload = m['unload'], ylim = tuple (m['ylim']))
else:
  s = SPRING (p, point, -1, point, m['spring'], direction = (-1, 0, 0), unload = m['unload'], ylim = tuple (m['ylim']))
pts = []
for t, v in zip (m['vt'], m['vx']):
  pts += [t, v]
vx = TSERIES (pts)
zero = TSERIES (0.0)
PRESCRIBE (p, (vx, zero, zero), (zero, zero, zero))
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'DX', 'VX'):
  H[e] = HISTORY (e, p)
for e in ('LENGTH', 'STROKE', 'F', 'SF', 'FF', 'SS'):
  H['spr0_' + e] = HISTORY (e, s)
DEM (m['duration'], step)
