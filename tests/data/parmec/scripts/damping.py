# Parmec-language script of the oracle case 'damping' (Parmec tests/damping.py): projectile with global
# linear DAMPING (1, 1, 1) under gravity.
v0 = (2.54, 0, 12.7)
stop = 1.976
step = stop / 1024.0
num = ANALYTICAL ([1, 1, 1, 0, 0, 0], 0.45359237, position=(0, 0, 0))
VELOCITY (num, v0, (0, 0, 0))
def lindamp(t): return (1, 1, 1)
def angdamp(t): return (0, 0, 0)
DAMPING (lindamp, angdamp)
GRAVITY (0., 0., -9.81456)
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'PY', 'PZ', 'VX', 'VY', 'VZ'):
  H[e] = HISTORY (e, num)
DEM (stop, step, (64*step, step))
