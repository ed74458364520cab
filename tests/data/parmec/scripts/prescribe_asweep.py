# Parmec-language script of the oracle case 'prescribe_asweep' (Parmec tests/prescribe_asweep.py with the
# oracle's parameters: sweep 0 -> 5 Hz over 5 s, h = 1e-3): unit cube driven by a prescribed linear
# acceleration (kind 'av', angular motion free).
from math import sin, pi
matnum = MATERIAL (1E3, 1E9, 0.25)
nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]
elements = [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum]
colors = [1, 4, 0, 1, 2, 3, 2, 4, 4, 5, 6, 7, 3]
parnum = MESH (nodes, elements, matnum, colors)
stop = 5.0
def linacc(t):
  amag, lofq, hifq = 1.0, 0.0, 5.0
  return (amag * sin (2.0*pi*(lofq+(hifq-lofq)*t/stop)*t), 0, 0)
PRESCRIBE (parnum, linear = linacc, kind = 'av')
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'DX', 'VX', 'FX'):
  H[e] = HISTORY (e, parnum)
DEM (stop, 0.001, (0.05, 0.01))
