# Parmec-language script of the oracle case 'restrain' (Parmec tests/restrain.py): 7 unit cubes,
# v0 = omega0 = (1, 1, 1), different RESTRAINs, no gravity. ARGV: [step] (default 0.1, the oracle's).
matnum = MATERIAL (1E3, 1E9, 0.25)
H = {'TIME': HISTORY ('TIME')}
for i in range (0, 7):
  nodes = [2*i, 2*i, 0, 2*i+1, 2*i, 0, 2*i+1, 2*i+1, 0, 2*i, 2*i+1, 0,
           2*i, 2*i, 1, 2*i+1, 2*i, 1, 2*i+1, 2*i+1, 1, 2*i, 2*i+1, 1]
  elements = [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum]
  parnum = MESH (nodes, elements, matnum, i+1)
  VELOCITY (parnum, (1, 1, 1), (1, 1, 1))
  if i == 1: RESTRAIN (parnum, [1, 0, 0])
  if i == 2: RESTRAIN (parnum, [1, 0, 0, 0, 1, 0])
  if i == 3: RESTRAIN (parnum, [1, 0, 0, 0, 1, 0, 0, 0, 1])
  if i == 4: RESTRAIN (parnum, angular = [1, 0, 0])
  if i == 5: RESTRAIN (parnum, angular = [1, 0, 0, 0, 1, 0])
  if i == 6: RESTRAIN (parnum, angular = [1, 0, 0, 0, 1, 0, 0 ,0, 1])
  for e in ('PX', 'PY', 'PZ', 'VX', 'VY', 'VZ', 'OX', 'OY', 'OZ'):
    H['p%d_%s' % (i, e)] = HISTORY (e, parnum)
DEM (5, float (ARGV()[0]) if ARGV() else 0.1)
