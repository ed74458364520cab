# Parmec-language script of the oracle case 'spring_friction_check': three analytical particles sliding at
# constant prescribed velocities over point-to-plane springs (plane z = 0 through their starting centres)
# with friction 0.3 and kskn 0, 0.5, 0.5 (sliding; fast: slip; slow: stick).
velocity = [(0.1, 0.05, -0.01), (0.1, 0.05, -0.01), (0.001, 0.0005, -0.01)]
kskn = [0.0, 0.5, 0.5]
H = {'TIME': HISTORY ('TIME')}
keep = []
for i in range (3):
  p = ANALYTICAL (position = (5.0 * i, 0, 0))
  VELOCITY (p, velocity[i])
  v = velocity[i]
  lin = lambda t, v = v: v
  ang = lambda t: (0, 0, 0)
  keep += [lin, ang]
  PRESCRIBE (p, lin, ang)
  s = SPRING (p, (5.0 * i, 0, 0), -1, [(5.0 * i, 0, 0), (0, 0, 1)], [-1.0, 1000.0, 0.0, 0.0, 1.0, 0.0],
              [-1.0, -10.0, 1.0, 10.0], friction = 0.3, kskn = kskn[i])
  for e in ('PX', 'PY', 'PZ', 'VX'):
    H['p%d_%s' % (i, e)] = HISTORY (e, p)
  for e in ('LENGTH', 'STROKE', 'F', 'SF', 'FF', 'SS'):
    H['spr%d_%s' % (s, e)] = HISTORY (e, s)
DEM (0.2, 0.001)
