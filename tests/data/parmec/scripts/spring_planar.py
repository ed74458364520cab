# Parmec-language script of the oracle case 'spring_planar' (Parmec tests/spring_planar.py): PLANAR spring
# (direction z), RESTRAINed z translation and rotations, initial velocity (0.5, 1, 0). ARGV: [step, duration].
exec (open (__file__.replace ('spring_planar.py', 'cube_common.py')).read ())
parnum = unit_cube ()
RESTRAIN (parnum, [0, 0, 1], [1, 0, 0, 0, 1, 0, 0, 0, 1])
s = SPRING (parnum, (.5, .5, 0), -1, (.5, .5, 0), [-1,-1E5, 1,1E5], [-1, -8E3, 1, 8E3], (0, 0, 1), 'ON')
VELOCITY (parnum, (.5, 1, 0))
H = histories (parnum, [s])
args = ARGV ()
h = float (args[0]) if args else 0.3 * CRITICAL ()
DEM (float (args[1]) if len (args) > 1 else 5.0, h)
