# Parmec-language script of the oracle case 'spring_damping_factor' (Parmec tests/spring_damping_factor.py):
# the hung cube with a critical damping ratio 1.0 instead of the dashpot table. ARGV: [step, duration].
exec (open (__file__.replace ('spring_damping_factor.py', 'cube_common.py')).read ())
parnum = unit_cube ()
s = SPRING (parnum, (1, 1, 1), -1, (1, 1, 1), [-1, -1E7, 1, 1E7], 1.0)
GRAVITY (0., 0., -10.)
H = histories (parnum, [s])
args = ARGV ()
h = float (args[0]) if args else 0.3 * CRITICAL ()
DEM (float (args[1]) if len (args) > 1 else 5.0, h)
