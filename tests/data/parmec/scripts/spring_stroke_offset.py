# Parmec-language script of the oracle case 'spring_stroke_offset' (Parmec tests/spring_stroke_offset.py):
# the hung cube with a stroke offset TSERIES [0,0, 5,0, 10,1, 15,1]. ARGV: [step, duration].
exec (open (__file__.replace ('spring_stroke_offset.py', 'cube_common.py')).read ())
parnum = unit_cube ()
ts = TSERIES ([0, 0, 5, 0, 10, 1, 15, 1])
s = SPRING (parnum, (1, 1, 1), -1, (1, 1, 1), [-1, -1E7, 1, 1E7], [-1, -8E5, 1, 8E5], offset = ts)
GRAVITY (0., 0., -10.)
H = histories (parnum, [s])
args = ARGV ()
h = float (args[0]) if args else 0.3 * CRITICAL ()
DEM (float (args[1]) if len (args) > 1 else 15.0, h)
