# Parmec-language script of the oracle case 'spring' (Parmec tests/spring.py): a unit cube hung by a
# FOLLOWER spring from its corner (1, 1, 1) to the same spatial point, dashpot table, gravity -10 z.
# ARGV(): [step, duration]; default step 0.3 CRITICAL(), duration 5 s.
matnum = MATERIAL (1E3, 1E9, 0.25)
nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]
elements = [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum]
parnum = MESH (nodes, elements, matnum, 1)
s = SPRING (parnum, (1, 1, 1), -1, (1, 1, 1), [-1, -1E7, 1, 1E7], [-1, -8E5, 1, 8E5])
GRAVITY (0., 0., -10.)
critical = CRITICAL ()
args = ARGV ()
step = float (args[0]) if args else 0.3 * critical
duration = float (args[1]) if len (args) > 1 else 5.0
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'PY', 'PZ', 'DX', 'DY', 'DZ', 'VX', 'VY', 'VZ', 'OX', 'OY', 'OZ', 'FX', 'FY', 'FZ', 'TX', 'TY', 'TZ'):
  H[e] = HISTORY (e, parnum)
for e in ('LENGTH', 'STROKE', 'F', 'SF', 'FF', 'SS'):
  H['spr0_' + e] = HISTORY (e, s)
DEM (duration, step)
