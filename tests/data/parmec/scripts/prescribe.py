# Parmec-language script of the oracle case 'prescribe' (Parmec tests/prescribe.py): unit cube with
# prescribed linear and angular velocity callbacks. ARGV: [step] (default 0.01, the oracle's).
matnum = MATERIAL (1E3, 1E9, 0.25)
nodes = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]
elements = [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum]
colors = [1, 4, 0, 1, 2, 3, 2, 4, 4, 5, 6, 7, 3]
parnum = MESH (nodes, elements, matnum, colors)
def linvel(t): return (t, 0, 0)
def angvel(t): return (0, 0, t)
PRESCRIBE (parnum, linvel, angvel)
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'DX', 'VX', 'OZ'):
  H[e] = HISTORY (e, parnum)
step = float (ARGV()[0]) if ARGV() else 0.01
DEM (2.0, step, (0.1, step))
