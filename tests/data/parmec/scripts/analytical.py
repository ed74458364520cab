# Parmec-language script of the oracle case 'analytical' (Parmec tests/analytical.py): a free analytical
# particle spinning about z; a material point (1, 0, 0) tracked.
matnum = MATERIAL (1E3, 1E9, 0.25)
parnum = ANALYTICAL ([1.0, 1.0, 1.0, 0.0, 0.0, 0.0], 1.0,
  [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0], (0.0, 0.0, 0.0), matnum)
VELOCITY (parnum, angular = (0, 0, 1))
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'OX', 'OY', 'OZ'):
  H[e] = HISTORY (e, parnum)
for e in ('PX', 'PY', 'PZ'):
  H['pt100_' + e] = HISTORY (e, parnum, point = (1, 0, 0))
DEM (10, 0.01, 0.1)
