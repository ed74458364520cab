#!/usr/bin/env python3
"""Reference geometry for tests/unit/mesh, computed by the INDEPENDENT Python model
../shared/oracle/liggghts-walls/spec_check_walls.py (bit-identical to LIGGGHTS 3.8 on every mesh
oracle case). Run once; the tests read only the files written here.

  python3 gen_mesh_geometry_ref.py /path/to/shared/oracle/liggghts-walls

Writes (next to this script): the STL files used, obtuse.stl (a synthetic mesh with obtuse
triangles, coplanar and folded shared edges), obtuse_corner.stl (one obtuse triangle), and *.ref files of lines 'keyword value...' with
doubles as C99 hex floats (exact)."""
import importlib.util
import math
import os
import random
import shutil
import sys

ORACLE = os.path.abspath(sys.argv[1])
HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location('scw', os.path.join(ORACLE, 'spec_check_walls.py'))
scw = importlib.util.module_from_spec(spec)
spec.loader.exec_module(scw)

STL = {'plate.stl': 'mesh_plate_diagonal', 'box.stl': 'mesh_box_edges_corner', 'paddle.stl': 'mesh_move_rotate_paddle',
       'pusher.stl': 'mesh_move_linear_pusher', 'funnel.stl': 'hopper200_funnel_settle'}
for name, case in STL.items():
    shutil.copy(os.path.join(ORACLE, case, name), os.path.join(HERE, name))


def h(x):
    return float(x).hex()


def hv(v):
    return ' '.join(h(c) for c in v)


def write_obtuse():
    """a small fan: triangles with an obtuse angle at node 2 (flagged), at node 0 (ignored by the
    quirk), two coplanar neighbours and one folded neighbour"""
    tris = [
        [[0.0, 0.0, 0.0], [0.04, 0.0, 0.0], [0.02, 0.004, 0.0]],      # obtuse at node 2
        [[0.02, 0.004, 0.0], [0.04, 0.0, 0.0], [0.035, 0.02, 0.0]],   # coplanar neighbour
        [[0.0, 0.0, 0.0], [0.02, 0.004, 0.0], [-0.01, 0.012, 0.0]],   # coplanar, obtuse at node 0 region
        [[0.0, 0.0, 0.0], [-0.002, -0.015, 0.012], [0.04, 0.0, 0.0]],  # folded down along the long edge
        [[0.035, 0.02, 0.0], [0.04, 0.0, 0.0], [0.06, 0.03, 0.01]],   # kinked neighbour
    ]
    with open(os.path.join(HERE, 'obtuse.stl'), 'w') as f:
        f.write('solid obtuse\n')
        for t in tris:
            f.write('  facet normal 0 0 0\n    outer loop\n')
            for p in t:
                f.write('      vertex %r %r %r\n' % tuple(p))
            f.write('    endloop\n  endfacet\n')
        f.write('endsolid obtuse\n')


def write_obtuse_corner():
    """one tilted triangle, obtuse at node 2 (the node LIGGGHTS flags), all edges and corners active:
    the obtuse-corner edge branches are reachable (in obtuse.stl that corner's edges are shared with
    coplanar neighbours, hence inactive)"""
    t = [[0.0, 0.0, 0.0], [0.04, 0.001, 0.003], [0.02, 0.005, 0.001]]
    with open(os.path.join(HERE, 'obtuse_corner.stl'), 'w') as f:
        f.write('solid obtuse_corner\n  facet normal 0 0 0\n    outer loop\n')
        for p in t:
            f.write('      vertex %r %r %r\n' % tuple(p))
        f.write('    endloop\n  endfacet\nendsolid obtuse_corner\n')


def write_snapped(src, dst, prec=1e-8):
    """the model compares nodes exactly, LIGGGHTS with the precision: funnel.stl has seam nodes
    1e-18 apart (y = -1.5e-18 vs 0). Snapping them to one value makes both rules agree."""
    seen = []
    with open(os.path.join(HERE, src)) as f, open(os.path.join(HERE, dst), 'w') as g:
        for line in f:
            t = line.split()
            if t and t[0] == 'vertex':
                p = [float(c) for c in t[1:4]]
                q = next((s for s in seen if all(abs(a - b) < prec for a, b in zip(p, s))), None)
                if q is None:
                    seen.append(p); q = p
                line = '      vertex %r %r %r\n' % tuple(q)
            g.write(line)


def dump_mesh(out, m):
    out.write('ntri %d\n' % m.n)
    for t in range(m.n):
        out.write('tri %d nodes %s\n' % (t, ' '.join(hv(p) for p in m.node[t])))
        out.write('tri %d geom %s %s %s %d %s\n' % (t, hv(m.el[t]), hv(m.sn[t]), ' '.join(hv(e) for e in m.ev[t]),
                                                     m.obtuse[t], h(m.rb[t])))
        out.write('tri %d active %s %s\n' % (t, ' '.join(str(int(x)) for x in m.edgeActive[t]),
                                             ' '.join(str(int(x)) for x in m.cornerActive[t])))
    for a in range(m.n):
        for b in range(m.n):
            if a != b and m.coplanar_node_neighs(a, b):
                out.write('coplanar %d %d\n' % (a, b))


def probes(out, m, rng, n_per_tri):
    for t in range(m.n):
        nd = m.node[t]
        rb = m.rb[t]
        c = [sum(p[k] for p in nd) / 3.0 for k in range(3)]
        pts = [list(p) for p in nd]                                           # exactly on nodes
        pts += [[0.5 * (nd[i][k] + nd[(i + 1) % 3][k]) for k in range(3)] for i in range(3)]  # edge midpoints
        for _ in range(n_per_tri):
            pts.append([c[k] + rng.uniform(-1.6, 1.6) * rb for k in range(3)])
        for p in pts:
            for r in (0.25 * rb, 0.9 * rb):
                q = [p[k] + m.sn[t][k] * rng.uniform(-0.8, 0.8) * r for k in range(3)]
                dn, delta, sign, bary = m.resolve(t, r, q)
                if delta is None:
                    out.write('probe %d %s %s none %s %d\n' % (t, hv(q), h(r), h(dn), sign))
                else:
                    out.write('probe %d %s %s hit %s %s %s %d\n' % (t, hv(q), h(r), h(dn), hv(delta), hv(bary), sign))


def obtuse_probes(out, m):
    """points in the wedge beyond each flagged obtuse corner (only that corner's barycentric
    coordinate positive), on a fixed fan of directions (no random numbers, so the other files'
    probes stay as they were), kept where the model's closest point lies on one of the corner's
    two edges: the obtuse-corner edge branches, whose barycentric weights feed the wall velocity"""
    for t in range(m.n):
        o = m.obtuse[t]
        if o < 0:
            continue
        nd, rb, sn = m.node[t], m.rb[t], m.sn[t]
        w1 = scw.sdiv(m.ev[t][o], scw.mag(m.ev[t][o]))
        w2 = scw.cross(sn, w1)
        for deg in range(0, 360, 5):
            th = math.radians(deg)
            u = [math.cos(th) * w1[k] + math.sin(th) * w2[k] for k in range(3)]
            for d, lift in ((0.1, 0.0), (0.25, 0.3), (0.5, -0.2)):
                r = 0.9 * rb
                q = [nd[o][k] + d * rb * u[k] + lift * r * sn[k] for k in range(3)]
                dn, delta, sign, bary = m.resolve(t, r, q)
                if delta is None or sign != 1 << o or bary[o] in (0.0, 1.0):
                    continue
                out.write('probe %d %s %s hit %s %s %s %d\n' % (t, hv(q), h(r), h(dn), hv(delta), hv(bary), sign))


def main():
    write_obtuse()
    write_obtuse_corner()
    write_snapped('funnel.stl', 'funnel_snapped.stl')
    rng = random.Random(20261125)
    for name in ('plate.stl', 'box.stl', 'paddle.stl', 'pusher.stl', 'funnel_snapped.stl', 'obtuse.stl'):
        m = scw.Mesh(scw.read_stl(os.path.join(HERE, name)))
        with open(os.path.join(HERE, name.replace('.stl', '.ref')), 'w') as out:
            out.write('# %s: spec_check_walls.Mesh topology/geometry and resolve() probes\n' % name)
            dump_mesh(out, m)
            probes(out, m, rng, 40 if m.n < 20 else 6)
    # placement (fix mesh/surface scale 0.8 rotate axis 1 0 0 angle 20 move 0 0 0.003, in that order)
    manip = [('scale', 0.8), ('rotate', ([1.0, 0.0, 0.0], 20.0)), ('move', [0.0, 0.0, 0.003])]
    tris = scw.manipulate(scw.read_stl(os.path.join(HERE, 'plate.stl')), manip)
    m = scw.Mesh(tris)
    with open(os.path.join(HERE, 'plate_placed.ref'), 'w') as out:
        out.write('# plate.stl with scale 0.8 rotate axis 1 0 0 angle 20 move 0 0 0.003\n')
        dump_mesh(out, m)
        probes(out, m, rng, 40)
    # motion: rotate (paddle, the oracle's mover), linear (pusher), and linear + rotate stacked
    with open(os.path.join(HERE, 'motion.ref'), 'w') as out:
        out.write('# move/mesh kinematics from spec_check_walls (rotate_incr, translate, recalc)\n')
        dt = 1e-6
        m = scw.Mesh(scw.read_stl(os.path.join(HERE, 'paddle.stl')))
        ax, org, om = [0.0, 0.0, 1.0], [0.0, 0.0, 0.0], 2. * math.pi / 0.2
        for step in range(1, 601):
            m.rotate_incr(om * dt, ax, org)
            ov = [ax[0] * om, ax[1] * om, ax[2] * om]
            m.vel = [[[0.0 + c for c in scw.cross(ov, [p[k] - org[k] for k in range(3)])] for p in nd] for nd in m.node]
            if step in (250, 499):
                m.recalc()
            if step in (1, 100, 250, 499, 600):
                out.write('rotate step %d\n' % step)
                for t in range(m.n):
                    out.write('state %d %s %s %s %s\n' % (t, ' '.join(hv(p) for p in m.node[t]), ' '.join(hv(e) for e in m.ev[t]),
                                                          hv(m.sn[t]), ' '.join(hv(v) for v in m.vel[t])))
        # stacked: linear v then rotate about an origin that moves with the mesh
        m = scw.Mesh(scw.read_stl(os.path.join(HERE, 'paddle.stl')))
        v = [0.1, -0.05, 0.02]
        ax = scw.sdiv([0.3, 0.4, 1.0], scw.mag([0.3, 0.4, 1.0]))
        org = [0.001, 0.002, 0.0]
        om = 2. * math.pi / 0.05
        for step in range(1, 301):
            dx = [v[0] * dt, v[1] * dt, v[2] * dt]
            m.translate(dx)
            org = [org[k] + dx[k] for k in range(3)]
            m.rotate_incr(om * dt, ax, org)
            ov = [ax[0] * om, ax[1] * om, ax[2] * om]
            m.vel = [[[(0.0 + v[k]) + c[k] for k in range(3)] for c in
                      (scw.cross(ov, [p[k] - org[k] for k in range(3)]) for p in nd)] for nd in m.node]
            if step in (1, 300):
                out.write('stacked step %d\n' % step)
                for t in range(m.n):
                    out.write('state %d %s %s %s %s\n' % (t, ' '.join(hv(p) for p in m.node[t]), ' '.join(hv(e) for e in m.ev[t]),
                                                          hv(m.sn[t]), ' '.join(hv(v_) for v_ in m.vel[t])))
    # the obtuse-corner edge branches (no random numbers: the files above are unchanged by it)
    m = scw.Mesh(scw.read_stl(os.path.join(HERE, 'obtuse_corner.stl')))
    with open(os.path.join(HERE, 'obtuse_corner.ref'), 'w') as out:
        out.write('# obtuse_corner.stl: spec_check_walls.Mesh geometry and resolve() probes beyond the obtuse corner\n')
        dump_mesh(out, m)
        obtuse_probes(out, m)


main()
