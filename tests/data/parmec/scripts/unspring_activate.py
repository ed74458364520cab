# Parmec-language script after Parmec's tests/unspring_activate.py: ten unit cubes along x tied by four
# zero-length springs per shared face, the last cube by four springs to space; each cube but the first has
# eight inactive point-to-plane springs (corners to the plane z = -5) that UNSPRING activates when it
# removes the four springs between cubes 4 and 5 (numbered from 0; SUM of their SF > 4e5); gravity. The
# first five cubes fall to the plane, the others hang from space, and the removed springs (still evaluated:
# Parmec reports their LENGTH) get longer than the ghost cutoff the front end starts with (3 m).
# ARGV: [step as a multiple of CRITICAL (default 0.05, Parmec's), duration (default 2 s), HISTORY interval
# (default every step)].
args = ARGV ()
matnum = MATERIAL (1E3, 1E9, 0.25)
plane_spring = [-1, 1E7, 0, 0, 1, 0]
face_spring = [-1, -1E7, 1, 1E7]
dashpot = [-1, -8E5, 1, 8E5]
faces = [(0, 0), (1, 0), (1, 1), (0, 1)]
face_springs, plane_springs = [], []
prev = -1
for i in range (10):
  nodes = [i, 0, 0, i+1, 0, 0, i+1, 1, 0, i, 1, 0, i, 0, 1, i+1, 0, 1, i+1, 1, 1, i, 1, 1]
  p = MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, matnum], matnum, 1)
  if prev >= 0:
    face_springs.append ([SPRING (p, (i, y, z), prev, (i, y, z), face_spring, dashpot) for y, z in faces])
    for c in range (0, 24, 3):
      plane_springs.append (SPRING (p, tuple (nodes[c:c+3]), -1, [(0, 0, -5), (0, 0, 1)], plane_spring,
                                    dashpot, inactive = True))
  prev = p
for y, z in faces:
  SPRING (p, (10, y, z), -1, (10, y, z), face_spring, dashpot)
UNSPRING (face_springs[4], face_springs[4], (None, 4E5), activate = plane_springs)
GRAVITY (0., 0., -10.)
H = {'TIME': HISTORY ('TIME'), 'PZ0': HISTORY ('PZ', 0), 'PX0': HISTORY ('PX', 0), 'PZ9': HISTORY ('PZ', 9),
     'PZ4': HISTORY ('PZ', 4), 'PZ5': HISTORY ('PZ', 5), 'LEN0': HISTORY ('LENGTH', face_springs[0][0]),
     'LEN_cut': HISTORY ('LENGTH', face_springs[4][0]), 'SS_cut': HISTORY ('SS', face_springs[4][0])}
h = (float (args[0]) if args else 0.05) * CRITICAL ()
DEM (float (args[1]) if len (args) > 1 else 2.0, h, (0.05, float (args[2]) if len (args) > 2 else h))
