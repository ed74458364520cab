# A Parmec model run unchanged by the dembridge front end (run from this folder):
#   python -m dembridge.parmec column.py [duration [amplitude]]      then: python plot_column.py
# A column of eight 1 m concrete-like blocks stacked on a shaking base (the kind of seismic rig Parmec is
# used for). Neighbouring blocks are tied by a BALL_JOINT at the centre of their common face and by four
# follower SPRINGs at the middles of the face's edges (tension/compression springs with a critical
# damping ratio) that give the column its bending stiffness (without them the jointed column is an
# inverted chain of pendulums and falls over). The base is PRESCRIBEd: three cycles of a 2 Hz horizontal
# motion of amplitude 0.1 m (velocity 0.2 pi f sin(2 pi f t), starting from rest), then rest.
# Writes out/column_history.csv (TIME, base and top displacement, top velocity, bottom joint reaction) and
# out/column0.pvd with its .vtu frames (the blocks' surfaces with their node velocities).
import math
import os

density = 2400.0
mat = MATERIAL (density, 3E10, 0.2)

def block (z0):
  nodes = [-0.5, -0.5, z0, 0.5, -0.5, z0, 0.5, 0.5, z0, -0.5, 0.5, z0,
           -0.5, -0.5, z0+1, 0.5, -0.5, z0+1, 0.5, 0.5, z0+1, -0.5, 0.5, z0+1]
  return MESH (nodes, [8, 0, 1, 2, 3, 4, 5, 6, 7, mat], mat, 1)

levels = 8
base = block (-1.0)
blocks = [block (float (k)) for k in range (levels)]

k = 5E8  # N/m per edge spring
table = [-1, -k, 1, k]
below = base
for k_, b in enumerate (blocks):
  z = float (k_)
  BALL_JOINT (b, (0, 0, z), below)
  for x, y in ((-0.5, 0), (0.5, 0), (0, -0.5), (0, 0.5)):
    SPRING (b, (x, y, z), below, (x, y, z), table, 0.05)
  below = b

f, cycles = 2.0, 3
amp = float (ARGV()[1]) if len (ARGV ()) > 1 else 0.1
def base_velocity (t):
  w = 2 * math.pi * f
  v = amp * w * math.sin (w * t) if t < cycles / f else 0.0  # displacement amp (1 - cos wt): starts at rest
  return (v, 0, 0)
def base_spin (t): return (0, 0, 0)
PRESCRIBE (base, base_velocity, base_spin)
GRAVITY (0., 0., -9.81)

top = blocks[-1]
T = HISTORY ('TIME')
xb = HISTORY ('DX', base)
xt = HISTORY ('DX', top)
zt = HISTORY ('DZ', top)
vt = HISTORY ('VX', top)
rx = HISTORY ('JREAC_X', 0)
rz = HISTORY ('JREAC_Z', 0)

# the blocks' surfaces with their node velocities every 0.05 s: out/column0.pvd (ParaView; plot_column.py draws one)
outdir = os.path.join (os.path.dirname (os.path.abspath (__file__)), 'out')  # DEM writes in the script's folder
os.makedirs (outdir, exist_ok = True)
OUTPUT (['NUMBER', 'LINVEL'], mode = ['MESH'])

h = 0.2 * CRITICAL ()
duration = float (ARGV()[0]) if ARGV () else 4.0
print ('critical step estimate %.3g s, step %.3g s' % (h / 0.2, h))
DEM (duration, h, (0.05, 0.005), 'out/column')

out = os.path.join (outdir, 'column_history.csv')
with open (out, 'w') as fh:
  fh.write ('TIME,base_DX,top_DX,top_DZ,top_VX,j0_JREAC_X,j0_JREAC_Z\n')
  for row in zip (T, xb, xt, zt, vt, rx, rz):
    fh.write (','.join (repr (v) for v in row) + '\n')
print ('top drift max %.4f m, bottom joint reaction |x| max %.4g N, weight above it %.4g N' %
       (max (abs (a - b) for a, b in zip (xt, xb)), max (abs (v) for v in rx), levels * density * 9.81))
