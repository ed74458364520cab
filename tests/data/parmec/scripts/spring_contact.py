# Parmec-language script of the oracle cases 'spring_contact', 'spring_contact_points' (CONSTANT-direction
# gap springs: ARGV[2] = 'points') and 'spring_contact_plane', 'spring_contact_plane_kskn' (point-to-plane
# springs with friction 0.1, kskn 0 or 0.5: ARGV[2] = 'plane' / 'plane_kskn'): a spinning cube dropped on
# four springs at its bottom corners. ARGV: [step, duration, variant].
exec (open (__file__.replace ('spring_contact.py', 'cube_common.py')).read ())
args = ARGV ()
variant = args[2] if len (args) > 2 else 'points'
parnum = unit_cube (1.0)
dashpot = [-1, -8E5, 1, 8E5]
springs = []
for x, y in ((0, 0), (1, 0), (1, 1), (0, 1)):
  if variant == 'points':
    springs.append (SPRING (parnum, (x, y, 1), -1, (x, y, 0), [0, 0, 1, 0, 2, 1E7], dashpot, direction = (0, 0, 1)))
  else:
    springs.append (SPRING (parnum, (x, y, 1), -1, [(x, y, 0), (0, 0, 1)], [-1, 1E7, 0, 0, 1, 0], dashpot,
                            friction = 0.1, kskn = 0.5 if variant == 'plane_kskn' else 0.0))
if variant == 'points':
  VELOCITY (parnum, angular = (0.25, 0.5, 0))
else:
  VELOCITY (parnum, (1, 1, 0), (0.25, 0.5, 1))
GRAVITY (0., 0., -10.)
H = histories (parnum, springs)
h = float (args[0]) if args else 0.1 * CRITICAL ()
DEM (float (args[1]) if len (args) > 1 else 5.0, h, (0.05, 10 * h))
