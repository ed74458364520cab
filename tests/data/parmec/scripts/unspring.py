# Parmec-language script of the oracle case 'unspring' (Parmec tests/unspring.py): ten unit cubes along x
# tied by four zero-length springs per shared face (the last cube by four springs to space), gravity;
# UNSPRING removes springs 16..19 when the SUM of their SF exceeds 4e5. ARGV: [step, duration].
args = ARGV ()
matnum = MATERIAL (1E3, 1E9, 0.25)
spring, dashpot = [-1, -1E7, 1, 1E7], [-1, -8E5, 1, 8E5]
faces = [(0, 0), (1, 0), (1, 1), (0, 1)]
prev = -1
for i in range (10):
  nodes = [i, 0, 0, i+1, 0, 0, i+1, 1, 0, i, 1, 0, i, 0, 1, i+1, 0, 1, i+1, 1, 1, i, 1, 1]
  p = MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum], matnum, 1)
  if prev >= 0:
    for y, z in faces:
      SPRING (p, (i, y, z), prev, (i, y, z), spring, dashpot)
  prev = p
for y, z in faces:
  SPRING (p, (10, y, z), -1, (10, y, z), spring, dashpot)
UNSPRING ([16, 17, 18, 19], [16, 17, 18, 19], (None, 4E5))
GRAVITY (0., 0., -10.)
H = {'TIME': HISTORY ('TIME'), 'sum16_19_SF': HISTORY ('SF', [16, 17, 18, 19]), 'spr16_SS': HISTORY ('SS', 16),
     'plast_PZ': HISTORY ('PZ', 9)}
h = float (args[0]) if args else 0.05 * CRITICAL ()
DEM (float (args[1]) if len (args) > 1 else 2.0, h)
