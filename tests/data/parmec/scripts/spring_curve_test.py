# Parmec-language script of the oracle case 'spring_curve_tests/caseNN' (Parmec tests/spring_curve_tests.py,
# one curve per run): an analytical particle on a CONSTANT-direction spring with the curve of ARGV[0]
# (CSV stroke,force) is moved back 1 m, then forward 2 m by prescribed velocities given between DEM calls;
# the history covers the forward sweep only.
import csv
h = 0.02
MATERIAL (1, 1, 0.25)
parnum = ANALYTICAL ()
ts = []
for r in csv.DictReader (open (ARGV()[0])):
  ts += [float (r['stroke']), float (r['force'])]
sprnum = SPRING (parnum, (0, 0, 0), -1, (0, 0, 0), ts, direction = (-1, 0, 0))
def lin0 (t): return (-1, 0, 0)
PRESCRIBE (parnum, linear = lin0)
DEM (1.0, h)
H = {'TIME': HISTORY ('TIME'), 'PX': HISTORY ('PX', parnum), 'VX': HISTORY ('VX', parnum)}
for e in ('LENGTH', 'STROKE', 'F', 'SF'):
  H['spr0_' + e] = HISTORY (e, sprnum)
def lin1 (t): return (1, 0, 0)
PRESCRIBE (parnum, linear = lin1)
DEM (2.0 + h, h)
