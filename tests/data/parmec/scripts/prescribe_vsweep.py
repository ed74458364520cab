# Parmec-language script of the oracle case 'prescribe_vsweep' (Parmec tests/prescribe_vsweep.py): unit
# cube driven by a prescribed linear velocity sweep (derivative of a 0 -> 5 Hz sine sweep), h = 1e-3.
from math import sin, cos, pi
matnum = MATERIAL (1E3, 1E9, 0.25)
nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]
elements = [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum]
colors = [1, 4, 0, 1, 2, 3, 2, 4, 4, 5, 6, 7, 3]
parnum = MESH (nodes, elements, matnum, colors)
stop = 5.0
def linvel(t):
  amag, lofq, hifq = 1.0, 0.0, 5.0
  v = amag * cos (2.0*pi*(lofq+(hifq-lofq)*t/stop)*t) * (2.0*pi*lofq + 4.0*pi*(hifq-lofq)*t/stop)
  return (v, 0, 0)
PRESCRIBE (parnum, linear = linvel)
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'DX', 'VX'):
  H[e] = HISTORY (e, parnum)
step = float (ARGV()[0]) if ARGV() else 0.001
DEM (stop, step, (0.05, 0.01))
