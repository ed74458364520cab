# Shared by the single-cube spring scripts (exec'd by them): the unit cube [0,1]^2 x [z0, z0+1] and the
# oracle's HISTORY columns of one particle and its springs.
def unit_cube (z0 = 0.0):
  matnum = MATERIAL (1E3, 1E9, 0.25)
  nodes = [0, 0, z0, 1, 0, z0, 1, 1, z0, 0, 1, z0, 0, 0, z0+1, 1, 0, z0+1, 1, 1, z0+1, 0, 1, z0+1]
  return MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum], matnum, [1, 4, 0, 1, 2, 3, 2, 4, 4, 5, 6, 7, 3])

def histories (parnum, springs, entities = ('LENGTH', 'STROKE', 'F', 'SF', 'FF', 'SS')):
  H = {'TIME': HISTORY ('TIME')}
  for e in ('PX', 'PY', 'PZ', 'DX', 'DY', 'DZ', 'VX', 'VY', 'VZ', 'OX', 'OY', 'OZ', 'FX', 'FY', 'FZ', 'TX', 'TY', 'TZ'):
    H[e] = HISTORY (e, parnum)
  for s in springs:
    for e in entities:
      H['spr%d_%s' % (s, e)] = HISTORY (e, s)
  return H
