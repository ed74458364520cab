# Parmec-language script of the oracle case 'spring_eqm_check': a unit cube [2,3]x[2,3]x[3,4] translated at a
# prescribed velocity (0.1, 0, 0) on a CONSTANT-direction spring (k = 1e4, critical damping ratio 0.5) from
# its corner (3, 2, 3) to that point in space: the dashpot coefficient shows the equivalent mass used
# (Parmec's quirk Q8: 6.62 instead of 250).
matnum = MATERIAL (1E3, 1E9, 0.25)
nodes = [2, 2, 3, 3, 2, 3, 3, 3, 3, 2, 3, 3, 2, 2, 4, 3, 2, 4, 3, 3, 4, 2, 3, 4]
p = MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum], matnum, 1)
s = SPRING (p, (3, 2, 3), -1, (3, 2, 3), [-1, -1E4, 1, 1E4], 0.5, direction = (1, 0, 0))
VELOCITY (p, (0.1, 0, 0))
lin = lambda t: (0.1, 0, 0)
ang = lambda t: (0, 0, 0)
PRESCRIBE (p, lin, ang)
H = {'TIME': HISTORY ('TIME')}
for e in ('PX', 'VX', 'OX', 'OY', 'OZ'):
  H[e] = HISTORY (e, p)
for e in ('LENGTH', 'STROKE', 'F', 'SF'):
  H['spr0_' + e] = HISTORY (e, s)
EQM_CORRECT = EQM (p, (3, 2, 3), direction = (1, 0, 0))
DEM (0.1, 0.001)
