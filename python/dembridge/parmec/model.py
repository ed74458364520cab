"""The Parmec input language (seed 000_06fddb409cce0c78, spec parmec-springs): every command checks its
arguments as Parmec does and records them in a Model; DEM hands the model to the LAMMPS runner.
Numbers returned to the script (particle, spring, TSERIES ... numbers) start at 0 as in Parmec."""
import math
import numbers
import os
import sys

from .errors import ParmecError, fail
from . import geometry as geo
from . import vtk_output

REAL_MAX = sys.float_info.max
# the Parmec commands of a script's namespace (and of the `parmec` module)
COMMANDS = ("ARGV", "RESET", "TSERIES", "MATERIAL", "SPHERE", "MESH", "ANALYTICAL", "OBSTACLE", "SPRING",
            "TORSION_SPRING", "UNSPRING", "BALL_JOINT", "EQM", "GRANULAR", "RESTRAIN", "PRESCRIBE", "VELOCITY",
            "GRAVITY", "DAMPING", "CRITICAL", "HISTORY", "OUTPUT", "DEM")


def _is_real(x):
    """A finite real number (not a bool): NaN and infinities are refused wherever a number is expected."""
    return isinstance(x, numbers.Real) and not isinstance(x, bool) and math.isfinite(x)


def _vec(cmd, name, v, n=3):
    if not isinstance(v, (tuple, list)) or len(v) != n or not all(_is_real(c) for c in v):
        fail(cmd, f"argument '{name}' must be a tuple of {n} finite numbers, got {v!r}")
    return [float(c) for c in v]


def _table(cmd, name, t):
    """Parmec lookup table [x1, y1, x2, y2, ...]: even length >= 4, x strictly increasing."""
    if not isinstance(t, (list, tuple)) or not all(_is_real(c) for c in t):
        fail(cmd, f"argument '{name}' must be a list [x1, y1, x2, y2, ...] of finite numbers, got {t!r}")
    if len(t) < 4 or len(t) % 2:
        fail(cmd, f"argument '{name}' must have an even number (>= 4) of entries, got {len(t)}")
    xs = t[0::2]
    if any(b <= a for a, b in zip(xs, xs[1:])):
        fail(cmd, f"argument '{name}': x values must increase strictly, got {list(xs)}")
    return [float(c) for c in t]


def tseries_value(ts, t):
    """Parmec's TMS_Value: a constant, or the linear spline through the points, constant outside them."""
    if ts[0] == "const":
        return ts[1]
    p = ts[1]
    if t <= p[0]:
        return p[1]
    for k in range(2, len(p), 2):
        if t <= p[k]:
            t0, v0, t1, v1 = p[k - 2], p[k - 1], p[k], p[k + 1]
            return v0 + (v1 - v0) * (t - t0) / (t1 - t0)
    return p[-1]


def _positive(cmd, name, v, t):
    if not _is_real(v) or not v > 0:
        fail(cmd, f"argument '{name}' gave {v!r} at t = {t!r}: an output interval must be a finite number > 0")
    return float(v)


def _checked_call(name, method):
    """The command as the script sees it: a call that does not fit the seed's signature (unknown keyword,
    missing or surplus argument) is a ParmecError naming the command, like every other bad argument."""
    import functools
    import inspect
    sig = inspect.signature(method)

    @functools.wraps(method)
    def command(*args, **kwargs):
        try:
            sig.bind(*args, **kwargs)
        except TypeError as e:
            raise ParmecError(f"{name}: {e} (expected {name}{sig})") from None
        return method(*args, **kwargs)
    return command


def _is_color(c):
    return isinstance(c, int) and not isinstance(c, bool) and c > 0


def _check_kwargs(cmd, kwargs, allowed):
    for k in kwargs:
        if k not in allowed:
            fail(cmd, f"unknown argument '{k}' (expected one of {', '.join(allowed)})")


class Particle:
    def __init__(self, kind, mass, centre, inertia, radius, material, color, rotation=None):
        self.kind = kind            # 'SPHERE', 'MESH', 'ANALYTICAL'
        self.mass = mass
        self.centre = centre        # reference mass centre X
        self.inertia = inertia      # referential 3x3 inertia about the centre
        self.radius = radius        # contact radius (SPHERE) or the isotropic-equivalent radius
        self.material = material
        self.color = color
        self.rotation = rotation or [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]
        self.analytical = kind == "ANALYTICAL"  # no contact shape (also a particle converted by ANALYTICAL)
        self.v = [0.0, 0.0, 0.0]
        self.w = [0.0, 0.0, 0.0]    # spatial angular velocity

    @property
    def contact_sphere(self):
        """A SPHERE that takes part in GRANULAR contact (not converted by ANALYTICAL)."""
        return self.kind == "SPHERE" and not self.analytical

    @property
    def contact_mesh(self):
        """A MESH whose boundary triangles take part in GRANULAR contact with spheres (not converted by ANALYTICAL)."""
        return self.kind == "MESH" and not self.analytical


class Model:
    """State of one Parmec session (RESET() empties it)."""

    def __init__(self, argv=None, script=None, quirks=False, workdir=None, comm=None):
        self.argv = list(argv or [])
        self.script = script
        self.quirks = quirks
        self.workdir = workdir
        self.comm = comm
        self.runner = None
        self.reset_state()

    # --------------------------------------------------------------------------------------------
    def reset_state(self):
        if getattr(self, "runner", None) is not None:
            self.runner.close()
        self.runner = None
        self.tseries = []           # [('const', v) | ('table', [t0, v0, ...])]
        self.materials = []         # (density, young, poisson)
        self.particles = []
        self.springs = []           # dicts
        self.joints = []            # (part1, part2 or -1, point)
        self.torsions = []
        self.unsprings = []
        self.restraints = {}        # particle -> (linear list, angular list)
        self.prescriptions = {}     # particle -> dict
        self.gravity = None         # 3 sources
        self.damping = None         # (3 linear, 3 angular sources)
        self.histories = []         # dicts with 'list'
        self.outputs = []
        self.granular = []          # pairing dicts, in call order (a later pairing of a pair wins)
        self.obstacles = []
        self.curtime = 0.0
        self.step_count = 0         # steps done over all DEM calls
        self.hist_time = 0.0        # Parmec's curtime_history
        self.out_time = 0.0         # Parmec's curtime_output
        self.prefix = None
        self.frozen = False         # LAMMPS deck built: model fixed
        self.motion_changed = False  # PRESCRIBE/GRAVITY/DAMPING given after a DEM call

    def namespace(self):
        ns = {n: _checked_call(n, getattr(self, n)) for n in COMMANDS}
        ns["__name__"] = "__main__"
        ns["__file__"] = self.script or "<parmec>"
        return ns

    def _modifiable(self, cmd):
        if self.frozen:
            fail(cmd, "changing the model after the first DEM() call is not supported (the LAMMPS model is built "
                      "at the first DEM; use RESET() to start a new model)")

    def _particle(self, cmd, name, i, allow_anchor=False):
        if allow_anchor and isinstance(i, int) and not isinstance(i, bool) and i == -1:
            return -1
        if not isinstance(i, int) or isinstance(i, bool) or not 0 <= i < len(self.particles):
            fail(cmd, f"argument '{name}' = {i!r} is not a particle number (0 ... {len(self.particles) - 1}"
                      f"{' or -1' if allow_anchor else ''})")
        return i

    def _tseries_ref(self, cmd, name, i):
        if not isinstance(i, int) or isinstance(i, bool) or not 0 <= i < len(self.tseries):
            fail(cmd, f"argument '{name}' = {i!r} is not a TSERIES number (0 ... {len(self.tseries) - 1})")
        return i

    def _source(self, cmd, name, g):
        """GRAVITY/DAMPING/PRESCRIBE component: float constant, int TSERIES number or callback."""
        if callable(g):
            return ("call", g)
        if isinstance(g, float):
            if not math.isfinite(g):
                fail(cmd, f"argument '{name}' must be a finite number, got {g!r}")
            return ("const", g)
        if isinstance(g, int) and not isinstance(g, bool):
            return ("tseries", self._tseries_ref(cmd, name, g))
        fail(cmd, f"argument '{name}' must be a float, a TSERIES number or a callable, got {g!r}")

    # ------------------------------------------------------------------------------------- commands
    def ARGV(self, nonparmec=True):
        if not isinstance(nonparmec, bool):
            fail("ARGV", f"argument 'nonparmec' must be True or False, got {nonparmec!r}")
        if nonparmec:
            return list(self.argv)
        return [self.script or ""] + list(self.argv)

    def RESET(self):
        self.reset_state()

    def TSERIES(self, points):
        cmd = "TSERIES"
        if _is_real(points):
            self.tseries.append(("const", float(points)))
            return len(self.tseries) - 1
        if isinstance(points, str):
            if not os.path.exists(points):
                fail(cmd, f"argument 'points': file '{points}' does not exist")
            vals = []
            with open(points) as f:
                for no, line in enumerate(f, 1):
                    for word in line.split("#")[0].split():
                        try:
                            v = float(word)
                        except ValueError:
                            v = math.nan
                        if not math.isfinite(v):
                            fail(cmd, f"argument 'points': file '{points}' line {no}: expected a finite number, "
                                      f"got {word!r}")
                        vals.append(v)
            points = vals
        if isinstance(points, (list, tuple)) and points and isinstance(points[0], (list, tuple)):
            flat = []
            for p in points:
                if not isinstance(p, (list, tuple)) or len(p) != 2:
                    fail(cmd, f"argument 'points': expected pairs [t, v], got {p!r}")
                flat += list(p)
            points = flat
        t = _table(cmd, "points", points)
        self.tseries.append(("table", t))
        return len(self.tseries) - 1

    def MATERIAL(self, density, young, poisson):
        cmd = "MATERIAL"
        for n, v in (("density", density), ("young", young), ("poisson", poisson)):
            if not _is_real(v):
                fail(cmd, f"argument '{n}' must be a finite number, got {v!r}")
        if density <= 0:
            fail(cmd, f"argument 'density' must be > 0, got {density}")
        if young <= 0 or not 0 <= poisson < 0.5:
            fail(cmd, f"young must be > 0 and 0 <= poisson < 0.5, got {young}, {poisson}")
        self.materials.append((float(density), float(young), float(poisson)))
        return len(self.materials) - 1

    def _material(self, cmd, m):
        if not isinstance(m, int) or isinstance(m, bool) or not 0 <= m < len(self.materials):
            fail(cmd, f"argument 'material' = {m!r} is not a material number (0 ... {len(self.materials) - 1})")
        return m

    def SPHERE(self, center, radius, material, color):
        cmd = "SPHERE"
        self._modifiable(cmd)
        c = _vec(cmd, "center", center)
        if not _is_real(radius) or radius <= 0:
            fail(cmd, f"argument 'radius' must be a finite number > 0, got {radius!r}")
        m = self._material(cmd, material)
        if not isinstance(color, int) or color <= 0:
            fail(cmd, f"argument 'color' must be a positive integer, got {color!r}")
        mass = self.materials[m][0] * 4.0 / 3.0 * math.pi * radius ** 3
        j = 0.4 * mass * radius * radius
        self.particles.append(Particle("SPHERE", mass, c, [[j, 0, 0], [0, j, 0], [0, 0, j]], float(radius), m, color))
        return len(self.particles) - 1

    def MESH(self, nodes, elements, material, colors):
        cmd = "MESH"
        self._modifiable(cmd)
        if not isinstance(nodes, (list, tuple)) or len(nodes) < 12 or len(nodes) % 3 or not all(_is_real(x) for x in nodes):
            fail(cmd, "argument 'nodes' must be a flat list [x0, y0, z0, x1, ...] of at least 4 nodes (finite numbers)")
        m = self._material(cmd, material)
        nn = len(nodes) // 3
        k = 0
        if not isinstance(elements, (list, tuple)) or not elements:
            fail(cmd, "argument 'elements' must be a non-empty list [n, i1, ..., in, material, ...]")
        while k < len(elements):
            n = elements[k]
            if n not in (4, 5, 6, 8):
                fail(cmd, f"argument 'elements': element node count must be 4, 5, 6 or 8, got {n!r} at entry {k}")
            if k + n + 2 > len(elements):
                fail(cmd, f"argument 'elements': element at entry {k} is truncated")
            for i in elements[k + 1:k + 1 + n]:
                if not isinstance(i, int) or not 0 <= i < nn:
                    fail(cmd, f"argument 'elements': node number {i!r} out of range 0 ... {nn - 1}")
            self._material(cmd, elements[k + 1 + n])
            k += n + 2
        if isinstance(colors, int):
            colors = [colors]
        if not isinstance(colors, (list, tuple)) or not colors or not _is_color(colors[0]):
            fail(cmd, f"argument 'colors' must be a positive integer or a list [gcolor, ...], got {colors!r}")
        faces = vtk_output.boundary_faces(elements)
        by_nodes = {frozenset(f): k for k, f in enumerate(faces)}
        face_color = [colors[0]] * len(faces)
        k = 1
        while k < len(colors):  # [gcolor, f1, n1, ..., nf1, c1, f2, ...]
            f = colors[k]
            if f not in (3, 4) or k + f + 2 > len(colors):
                fail(cmd, f"argument 'colors': entry {k} must start a face 'f, n1, ..., nf, color' with f = 3 or 4 "
                          f"nodes, got {list(colors[k:k + 6])!r}")
            nodes_k, c = colors[k + 1:k + 1 + f], colors[k + 1 + f]
            if not all(isinstance(i, int) and 0 <= i < nn for i in nodes_k) or not _is_color(c):
                fail(cmd, f"argument 'colors': face {list(nodes_k)!r} with colour {c!r}: node numbers must be "
                          f"0 ... {nn - 1} and the colour a positive integer")
            face = by_nodes.get(frozenset(nodes_k))
            if face is None:
                fail(cmd, f"argument 'colors': face {list(nodes_k)!r} is not a boundary face of the mesh")
            face_color[face] = c
            k += f + 2
        dens = {i: mat[0] for i, mat in enumerate(self.materials)}
        try:
            mass, centre, J, vol = geo.mesh_mass_properties(nodes, elements, dens)
        except ZeroDivisionError:
            vol = 0.0
        if not vol > 0.0:
            fail(cmd, f"the elements enclose no volume (zero-volume mesh: coincident or coplanar nodes); a MESH "
                      f"particle needs a positive volume, got nodes {list(nodes)!r}")
        r = math.sqrt((J[0][0] + J[1][1] + J[2][2]) / 3.0 / (0.4 * mass))
        p = Particle("MESH", mass, centre, J, r, m, colors[0])
        p.nodes = [float(x) for x in nodes]
        p.triangles = [t for f in faces for t in vtk_output.fan(f)]
        p.triangle_colors = [c for f, c in zip(faces, face_color) for _ in vtk_output.fan(f)]
        self.particles.append(p)
        return len(self.particles) - 1

    def ANALYTICAL(self, inertia=None, mass=None, rotation=None, position=None, material=None, particle=None):
        """A body without contact shape; particle=i converts particle i (its shape kept for output, its
        properties inherited unless given) and returns i."""
        cmd = "ANALYTICAL"
        self._modifiable(cmd)
        base = None if particle is None else self.particles[self._particle(cmd, "particle", particle)]
        if inertia is None:
            J = [list(r) for r in base.inertia] if base else [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]
        else:
            if not isinstance(inertia, (list, tuple)) or len(inertia) != 6 or not all(_is_real(x) for x in inertia):
                fail(cmd, f"argument 'inertia' must be a list [Ixx, Iyy, Izz, Ixy, Ixz, Iyz], got {inertia!r}")
            J = [[inertia[0], inertia[3], inertia[4]], [inertia[3], inertia[1], inertia[5]],
                 [inertia[4], inertia[5], inertia[2]]]
            try:
                geo.inv3(J)
            except ZeroDivisionError:
                fail(cmd, f"argument 'inertia' is singular: {inertia!r}")
            if min(inertia[:3]) <= 0:
                fail(cmd, f"argument 'inertia': diagonal entries must be > 0, got {inertia!r}")
        if mass is None:
            mass = base.mass if base else 1.0
        if not _is_real(mass) or mass <= 0:
            fail(cmd, f"argument 'mass' must be a finite number > 0, got {mass!r}")
        rot = [list(r) for r in base.rotation] if base else [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]
        if rotation is not None:
            r = _vec(cmd, "rotation", rotation, 9)
            rot = [[r[0], r[3], r[6]], [r[1], r[4], r[7]], [r[2], r[5], r[8]]]  # columns e1, e2, e3
            for i in range(3):
                for j in range(3):
                    d = sum(rot[k][i] * rot[k][j] for k in range(3))
                    if abs(d - (1.0 if i == j else 0.0)) > 1e-10:
                        fail(cmd, "argument 'rotation': vectors e1, e2, e3 must be orthonormal")
        if position is None:
            pos = list(base.centre) if base else [0.0, 0.0, 0.0]
        else:
            pos = _vec(cmd, "position", position)
        mat = (base.material if base else 0) if material is None else material
        if self.materials or material is not None:
            self._material(cmd, mat)
        r = math.sqrt((J[0][0] + J[1][1] + J[2][2]) / 3.0 / (0.4 * mass))
        if base is None:
            self.particles.append(Particle("ANALYTICAL", float(mass), pos, J, r, mat, 0, rot))
            return len(self.particles) - 1
        # the reference centre moves to 'position' (the shape stays where it is: drawn at x + L (P - X))
        base.mass, base.centre, base.inertia, base.radius, base.material, base.rotation = \
            float(mass), pos, J, r, mat, rot
        base.analytical = True
        return particle

    def OBSTACLE(self, triangles, color, point=None, linear=None, angular=None):
        """A static or moving triangle set (fix parmec/granular). linear/angular: callbacks f(t) -> (x, y, z)
        (Parmec) or tuples of 3 TSERIES numbers; a moving obstacle needs its reference 'point'."""
        cmd = "OBSTACLE"
        self._modifiable(cmd)
        if not isinstance(triangles, (list, tuple)) or not triangles:
            fail(cmd, f"argument 'triangles' must be a non-empty list of 9-tuples (x1, y1, z1, ..., z3), got {triangles!r}")
        tris = []
        for k, t in enumerate(triangles):
            if not isinstance(t, (tuple, list)) or len(t) != 9 or not all(_is_real(c) for c in t):
                fail(cmd, f"argument 'triangles': triangle {k} must be a tuple of 9 numbers, got {t!r}")
            a, b, c = [float(x) for x in t[0:3]], [float(x) for x in t[3:6]], [float(x) for x in t[6:9]]
            e1, e2 = [b[i] - a[i] for i in range(3)], [c[i] - a[i] for i in range(3)]
            n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
            if not all(math.isfinite(x) for x in a + b + c) or math.sqrt(sum(x * x for x in n)) == 0.0:
                fail(cmd, f"argument 'triangles': triangle {k} is degenerate (zero area or not finite): {tuple(t)!r}")
            tris.append(a + b + c)
        if isinstance(color, int) and not isinstance(color, bool):
            colors = [color] * len(tris)
        elif isinstance(color, (list, tuple)):
            if len(color) != len(tris):
                fail(cmd, f"argument 'color': expected one colour per triangle ({len(tris)}), got {len(color)}")
            colors = list(color)
        else:
            fail(cmd, f"argument 'color' must be a positive integer or a list of them, got {color!r}")
        for c in colors:
            if not isinstance(c, int) or isinstance(c, bool) or c <= 0:
                fail(cmd, f"argument 'color' must be a positive integer (or a list of them), got {c!r}")
        ob = {"triangles": tris, "colors": colors, "point": None, "linear": None, "angular": None}
        if point is not None:
            ob["point"] = _vec(cmd, "point", point)
        for name, v in (("linear", linear), ("angular", angular)):
            if v is not None:
                ob[name] = self._triple(cmd, name, v)
        if (linear is not None or angular is not None) and point is None:
            fail(cmd, "argument 'point' is required with 'linear' or 'angular' (Parmec silently keeps such an "
                      "obstacle static)")
        self.obstacles.append(ob)

    def BALL_JOINT(self, part1, point, part2=None):
        cmd = "BALL_JOINT"
        self._modifiable(cmd)
        i = self._particle(cmd, "part1", part1)
        j = -1 if part2 is None else self._particle(cmd, "part2", part2)
        if i == j:
            fail(cmd, f"argument 'part2' = {part2!r} is part1: a joint needs two different particles")
        p = _vec(cmd, "point", point)
        for k, (a, b, q) in enumerate(self.joints):
            if a == i and b == j and q == p:
                fail(cmd, f"joint {k} already joins these particles at {tuple(p)} (a redundant joint makes the "
                          "joint system singular)")
        self.joints.append((i, j, p))
        return len(self.joints) - 1

    def GRANULAR(self, color1, color2, spring, damper=1.0, friction=0.0, rolling=0.0, drilling=0.0, kskn=0.5):
        """A pairing of surface colours (spec §11); (0, 0) redefines the default of unspecified pairings."""
        cmd = "GRANULAR"
        self._modifiable(cmd)
        for n, v in (("color1", color1), ("color2", color2)):
            if not isinstance(v, int) or isinstance(v, bool) or v < 0:
                fail(cmd, f"argument '{n}' must be an integer >= 0, got {v!r}")
        if (color1 == 0) != (color2 == 0):
            fail(cmd, f"arguments 'color1', 'color2' = ({color1}, {color2}): colour 0 only as (0, 0), the default "
                      "of unspecified pairings")
        for n, v in (("spring", spring), ("damper", damper), ("kskn", kskn)):
            if not _is_real(v) or not math.isfinite(v) or v < 0:
                fail(cmd, f"argument '{n}' must be a number >= 0, got {v!r}")
        if _is_real(friction):
            mus = mud = friction
        elif isinstance(friction, (tuple, list)) and len(friction) == 2 and all(_is_real(f) for f in friction):
            mus, mud = friction
        else:
            fail(cmd, f"argument 'friction' must be a number or a tuple (static, dynamic), got {friction!r}")
        if not (math.isfinite(mus) and math.isfinite(mud)) or mus < 0 or mud < 0:
            fail(cmd, f"argument 'friction' must be >= 0, got {friction!r}")
        for n, v in (("rolling", rolling), ("drilling", drilling)):
            if not _is_real(v):
                fail(cmd, f"argument '{n}' must be a number, got {v!r}")
            if v != 0:
                fail(cmd, f"argument '{n}' = {v!r} is not supported (Parmec's {n} friction is under development "
                          "and has no effect there)")
        self.granular.append({"color1": color1, "color2": color2, "spring": float(spring), "damper": float(damper),
                              "mus": float(mus), "mud": float(mud), "kskn": float(kskn)})

    def contact_active(self):
        """Some pairing (the default included) has spring > 0."""
        default = 0.0
        for g in self.granular:
            if g["color1"] == 0:
                default = g["spring"]
        return default > 0 or any(g["spring"] > 0 for g in self.granular)

    def _no_mesh_mesh_contact(self, cmd):
        """SPHERE-MESH contact is supported; two MESH particles whose face colours have a pairing with spring > 0
        are refused (MESH-MESH contact is out of scope, and not implemented in Parmec either). Checked at DEM, when
        the pairings are final (a later GRANULAR(c1, c2, 0.0) may switch a pair off)."""
        from .contact_step import _pairing
        if not self.contact_active():
            return
        pairing = _pairing(self)
        meshes = [(i, sorted(set(p.triangle_colors))) for i, p in enumerate(self.particles) if p.contact_mesh]
        for a, (i, ci) in enumerate(meshes):
            for j, cj in meshes[a + 1:]:
                for c1 in ci:
                    for c2 in cj:
                        if pairing(c1, c2)[0] > 0:
                            fail(cmd, f"MESH particles {i} and {j}: the GRANULAR pairing of their colours ({c1}, {c2}) "
                                      "has spring > 0, but contact between two MESH particles is not supported (out of "
                                      "scope, and not implemented in Parmec either); give that colour pair spring 0 "
                                      "(e.g. GRANULAR(c1, c2, 0.0)) or use SPHEREs")

    def VELOCITY(self, parnum, linear=None, angular=None):
        cmd = "VELOCITY"
        self._modifiable(cmd)
        i = self._particle(cmd, "parnum", parnum)
        if linear is not None:
            self.particles[i].v = _vec(cmd, "linear", linear)
        if angular is not None:
            self.particles[i].w = _vec(cmd, "angular", angular)

    def GRAVITY(self, gx, gy, gz):
        cmd = "GRAVITY"
        self.motion_changed = self.frozen  # allowed between DEM calls (re-sent at the next DEM)
        self.gravity = [self._source(cmd, n, g) for n, g in (("gx", gx), ("gy", gy), ("gz", gz))]

    def _triple(self, cmd, name, v):
        if callable(v):
            return ("call3", v)
        if isinstance(v, (tuple, list)) and len(v) == 3:
            return ("tseries3", [self._tseries_ref(cmd, name, t) for t in v])
        fail(cmd, f"argument '{name}' must be a callable returning (x, y, z) or a tuple of 3 TSERIES numbers, got {v!r}")

    def DAMPING(self, linear, angular):
        cmd = "DAMPING"
        self.motion_changed = self.frozen  # allowed between DEM calls (re-sent at the next DEM)
        self.damping = (self._triple(cmd, "linear", linear), self._triple(cmd, "angular", angular))

    def RESTRAIN(self, parnum, linear=None, angular=None):
        cmd = "RESTRAIN"
        self._modifiable(cmd)
        i = self._particle(cmd, "parnum", parnum)
        out = []
        for name, d in (("linear", linear), ("angular", angular)):
            if d is None:
                out.append([])
                continue
            if not isinstance(d, (list, tuple)) or len(d) not in (3, 6, 9) or not all(_is_real(x) for x in d):
                fail(cmd, f"argument '{name}' must be a list of 3, 6 or 9 numbers (1 to 3 directions), got {d!r}")
            for k in range(0, len(d), 3):
                if all(x == 0 for x in d[k:k + 3]) and len(d) > 3:
                    fail(cmd, f"argument '{name}': direction {k // 3 + 1} is zero")
            out.append([float(x) for x in d] if any(x != 0 for x in d) else [])
        if i in self.restraints:
            lin0, ang0 = self.restraints[i]
            out = [lin0 + out[0], ang0 + out[1]]
            if len(out[0]) > 9 or len(out[1]) > 9:
                fail(cmd, f"particle {i}: more than 3 restrained directions")
        self.restraints[i] = out

    def PRESCRIBE(self, parnum, linear=None, angular=None, kind="vv"):
        cmd = "PRESCRIBE"
        self.motion_changed = self.frozen  # allowed between DEM calls (re-sent at the next DEM)
        i = self._particle(cmd, "parnum", parnum)
        if kind not in ("vv", "va", "av", "aa"):
            fail(cmd, f"argument 'kind' must be 'vv', 'va', 'av' or 'aa', got {kind!r}")
        if linear is None and angular is None:
            fail(cmd, "expected 'linear' and/or 'angular'")
        self.prescriptions[i] = {
            "linear": None if linear is None else self._triple(cmd, "linear", linear),
            "angular": None if angular is None else self._triple(cmd, "angular", angular),
            "kind": kind}

    def SPRING(self, part1, point1, part2, geom2, spring, dashpot=None, direction=None, planar=None, unload=None,
               ylim=None, inactive=False, offset=None, friction=0.0, kskn=0.0):
        cmd = "SPRING"
        self._modifiable(cmd)
        i = self._particle(cmd, "part1", part1)
        j = self._particle(cmd, "part2", part2, allow_anchor=True)
        p1 = _vec(cmd, "point1", point1)
        plane = None
        if isinstance(geom2, list) and len(geom2) == 2 and all(isinstance(g, (tuple, list)) for g in geom2):
            p2 = _vec(cmd, "geom2 point", geom2[0])
            plane = _vec(cmd, "geom2 normal", geom2[1])
            if all(c == 0 for c in plane):
                fail(cmd, "argument 'geom2': the plane normal is zero")
        else:
            p2 = _vec(cmd, "geom2", geom2)
        s = {"part1": i, "part2": j, "point1": p1, "point2": p2, "plane": plane,
             "spring": _table(cmd, "spring", spring), "inactive": bool(inactive)}
        if dashpot is not None:
            if _is_real(dashpot):
                if dashpot < 0:
                    fail(cmd, f"argument 'dashpot': a critical damping ratio must be >= 0, got {dashpot}")
                s["ratio"] = float(dashpot)
            else:
                s["dashpot"] = _table(cmd, "dashpot", dashpot)
        if direction is not None:
            d = _vec(cmd, "direction", direction)
            if all(c == 0 for c in d):
                fail(cmd, "argument 'direction' must be non-zero")
            s["direction"] = d
        if planar is not None:
            if planar not in ("ON", "OFF"):
                fail(cmd, f"argument 'planar' must be 'ON' or 'OFF', got {planar!r}")
            if planar == "ON" and direction is None:
                fail(cmd, "argument 'planar' = 'ON' needs a 'direction'")
            s["planar"] = planar == "ON"
        if unload is not None:
            u = _table(cmd, "unload", unload)
            ys = u[1::2]
            if any(b <= a for a, b in zip(ys, ys[1:])):
                fail(cmd, "argument 'unload' must be strictly increasing")
            s["unload"] = u
        if ylim is not None:
            y = _vec(cmd, "ylim", ylim, 2)
            if not y[0] <= 0 <= y[1]:
                fail(cmd, f"argument 'ylim' must satisfy ylim[0] <= 0 <= ylim[1], got {ylim!r}")
            s["ylim"] = y
        if offset is not None:
            k = self._tseries_ref(cmd, "offset", offset)
            if self.tseries[k][0] == "const":
                fail(cmd, f"argument 'offset': TSERIES {k} is a constant; an offset needs >= 2 points")
            s["offset"] = k
        if not _is_real(friction) or friction < 0:
            fail(cmd, f"argument 'friction' must be a number >= 0, got {friction!r}")
        if not _is_real(kskn) or kskn < 0:
            fail(cmd, f"argument 'kskn' must be a number >= 0, got {kskn!r}")
        s["friction"], s["kskn"] = float(friction), float(kskn)
        self.springs.append(s)
        return len(self.springs) - 1

    def TORSION_SPRING(self, part1, part2, zdir, xdir, kroll=None, kpitch=None, kyaw=None, droll=None, dpitch=None,
                       dyaw=None, cone=None, refpnt=None):
        cmd = "TORSION_SPRING"
        self._modifiable(cmd)
        i = self._particle(cmd, "part1", part1)
        j = self._particle(cmd, "part2", part2, allow_anchor=True)
        z, x = _vec(cmd, "zdir", zdir), _vec(cmd, "xdir", xdir)
        nz, nx = math.sqrt(sum(c * c for c in z)), math.sqrt(sum(c * c for c in x))
        if nz == 0 or nx == 0:
            fail(cmd, "arguments 'zdir' and 'xdir' must be non-zero")
        if abs(sum(a * b for a, b in zip(z, x))) / (nz * nx) > 1e-8:
            fail(cmd, f"arguments 'zdir' {zdir!r} and 'xdir' {xdir!r} must be orthogonal")
        t = {"part1": i, "part2": j, "zdir": z, "xdir": x}
        for name, v in (("kroll", kroll), ("kpitch", kpitch), ("kyaw", kyaw)):
            if v is not None:
                t[name] = _table(cmd, name, v)
        for name, v in (("droll", droll), ("dpitch", dpitch), ("dyaw", dyaw)):
            if v is None:
                continue
            if _is_real(v):
                if v < 0:
                    fail(cmd, f"argument '{name}': a critical damping ratio must be >= 0, got {v}")
                t[name] = float(v)
            else:
                t[name] = _table(cmd, name, v)
        if cone is not None:
            if not isinstance(cone, (tuple, list)) or len(cone) not in (2, 3) or len(set(cone)) != len(cone) or \
                    any(c not in ("roll", "pitch", "yaw") for c in cone):
                fail(cmd, f"argument 'cone' must be 2 or 3 distinct names of 'roll', 'pitch', 'yaw', got {cone!r}")
            t["cone"] = list(cone)
        if refpnt is not None:
            t["refpnt"] = _vec(cmd, "refpnt", refpnt)
        self.torsions.append(t)
        return len(self.torsions) - 1

    def UNSPRING(self, tsprings, msprings, limits, entity="SF", operator="SUM", abs=False, nsteps=1, nfreq=1,
                 unload=None, activate=None):
        cmd = "UNSPRING"
        self._modifiable(cmd)
        for name, lst in (("tsprings", tsprings), ("msprings", msprings)):
            if not isinstance(lst, (list, tuple)) or not lst:
                fail(cmd, f"argument '{name}' must be a non-empty list of spring numbers")
            if len(set(lst)) != len(lst):
                fail(cmd, f"argument '{name}' lists a spring twice: {list(lst)}")
            for s in lst:
                if not isinstance(s, int) or not 0 <= s < len(self.springs):
                    fail(cmd, f"argument '{name}': {s!r} is not a spring number (0 ... {len(self.springs) - 1})")
        if not isinstance(limits, (tuple, list)) or len(limits) != 2:
            fail(cmd, f"argument 'limits' must be a tuple (min, max), got {limits!r}")
        lo = -REAL_MAX if limits[0] is None else limits[0]
        hi = REAL_MAX if limits[1] is None else limits[1]
        if not lo < hi:
            fail(cmd, f"argument 'limits' must satisfy min < max, got {limits!r}")
        if entity not in ("STROKE", "F", "SF", "FF"):
            fail(cmd, f"argument 'entity' must be 'STROKE', 'F', 'SF' or 'FF', got {entity!r}")
        if operator not in ("SUM", "MIN", "MAX"):
            fail(cmd, f"argument 'operator' must be 'SUM', 'MIN' or 'MAX', got {operator!r}")
        for name, v in (("nsteps", nsteps), ("nfreq", nfreq)):
            if not isinstance(v, int) or v < 1:
                fail(cmd, f"argument '{name}' must be an integer >= 1, got {v!r}")
        umap = {}
        if unload is not None:
            if isinstance(unload, dict):
                for k, v in unload.items():
                    if k not in msprings:
                        fail(cmd, f"argument 'unload': spring {k!r} is not in msprings")
                    umap[k] = self._tseries_ref(cmd, "unload", v)
            else:
                umap = {None: self._tseries_ref(cmd, "unload", unload)}
            for k in umap.values():
                if self.tseries[k][0] == "const":
                    fail(cmd, f"argument 'unload': TSERIES {k} is a constant; an unload curve needs >= 2 points")
        act = list(activate or [])
        for s in act:
            if not isinstance(s, int) or not 0 <= s < len(self.springs):
                fail(cmd, f"argument 'activate': {s!r} is not a spring number")
            if not self.springs[s]["inactive"]:
                fail(cmd, f"argument 'activate': spring {s} is not inactive")
        for u in self.unsprings:
            both = set(u["msprings"]) & set(msprings)
            if both:
                fail(cmd, f"springs {sorted(both)} are already managed by an earlier UNSPRING")
        for s in msprings:
            if self.springs[s]["inactive"]:
                fail(cmd, f"argument 'msprings': spring {s} is inactive")
        self.unsprings.append({"tsprings": list(tsprings), "msprings": list(msprings), "limits": (lo, hi),
                               "entity": entity, "operator": operator, "abs": bool(abs), "nsteps": nsteps,
                               "nfreq": nfreq, "unload": umap, "activate": act})
        return len(self.unsprings) - 1

    def EQM(self, part1, point1, part2=None, point2=None, direction=None):
        """Equivalent point mass (spec §12); quirk Q17 fixed: the minimum eigenvalue of M⁻¹ always."""
        cmd = "EQM"
        parts = [(self._particle(cmd, "part1", part1), _vec(cmd, "point1", point1))]
        if part2 is not None:
            parts.append((self._particle(cmd, "part2", part2), _vec(cmd, "point2", point2)))
        Minv = [[0.0] * 3 for _ in range(3)]
        for i, P in parts:
            p = self.particles[i]
            A = [p.centre[c] - P[c] for c in range(3)]
            Ax = [[0, -A[2], A[1]], [A[2], 0, -A[0]], [-A[1], A[0], 0]]
            Ji = geo.inv3(p.inertia)
            for r in range(3):
                for c in range(3):
                    s = sum(Ax[k][r] * sum(Ji[k][l] * Ax[l][c] for l in range(3)) for k in range(3))
                    Minv[r][c] += s + (1.0 / p.mass if r == c else 0.0)
        if direction is not None:
            d = _vec(cmd, "direction", direction)
            if any(c != 0 for c in d):
                return 1.0 / sum(d[r] * sum(Minv[r][c] * d[c] for c in range(3)) for r in range(3))
        import numpy as np
        return 1.0 / float(min(np.linalg.eigvalsh(np.array(Minv))))

    def CRITICAL(self, perspring=None, perparticle=None):
        cmd = "CRITICAL"
        counts = {"perspring": len(self.springs), "perparticle": len(self.particles)}
        args = {}
        for name, v in (("perspring", perspring), ("perparticle", perparticle)):
            if v is None:
                args[name] = -1
            elif not isinstance(v, int) or isinstance(v, bool) or not 0 <= v <= counts[name]:
                fail(cmd, f"argument '{name}' must be an integer 0 ... {counts[name]}, got {v!r}")
            else:
                args[name] = v
        from .runner import critical_step
        return critical_step(self, **args)

    def HISTORY(self, entity, source=0, point=None, h5file=None, h5last=False):
        cmd = "HISTORY"
        from .history import request
        if h5file is not None:
            fail(cmd, "argument 'h5file' (reading histories from Parmec's .h5 output) is not supported")
        if h5last:
            fail(cmd, "argument 'h5last' (with h5file, reading histories from Parmec's .h5 output) is not supported")
        return request(self, entity, source, point)

    def OUTPUT(self, entities=None, subset=None, mode=None, format=None):
        cmd = "OUTPUT"
        # Parmec's default is XDMF (+HDF5); here VTK, which ParaView opens the same way
        fmts = format if isinstance(format, (list, tuple)) else [format or "VTK"]
        for f in fmts:
            if f not in ("DUMP", "VTK", "XDMF", "MED"):
                fail(cmd, f"argument 'format': unknown format {f!r}")
            if f not in ("DUMP", "VTK"):
                fail(cmd, f"argument 'format' = {f!r} is not supported (only 'VTK': VTK XML files with a .pvd time "
                          "series, and 'DUMP': LAMMPS dump files, both open in ParaView)")
        if subset is not None:
            sub = subset if isinstance(subset, (list, tuple)) else [subset]
            for i in sub:
                self._particle(cmd, "subset", i)
        else:
            sub = None
        modes = None
        if mode is not None:
            modes = list(mode) if isinstance(mode, (list, tuple)) else [mode]
            for m in modes:
                if m not in ("SPH", "MESH", "RB", "CD", "SL", "ST", "TS", "JT"):
                    fail(cmd, f"argument 'mode': unknown mode {m!r} (expected 'SPH', 'MESH', 'RB', 'CD', 'SL', "
                              "'ST' (or 'TS'), 'JT')")
            # the seed names the torsion spring mode 'ST' in the mode list and 'TS' in the entity list
            modes = list(dict.fromkeys("ST" if m == "TS" else m for m in modes))
        if entities is not None:
            known = {"NUMBER", "COLOR", "DISPL", "LENGTH", "ORIENT", "ORIENT1", "ORIENT2", "ORIENT3", "LINVEL",
                     "ANGVEL", "FORCE", "TORQUE", "F", "FN", "FT", "SF", "FF", "SS", "AREA", "PAIR", "XDIR", "YDIR",
                     "ZDIR", "TRQROT", "TRQTOT", "TRQSPR", "JREAC"}
            for e in entities:
                if e not in known:
                    fail(cmd, f"argument 'entities': unknown entity {e!r}")
        self._modifiable(cmd)
        if "DUMP" in fmts and "VTK" not in fmts and modes and set(modes) - {"SPH", "RB"}:
            fail(cmd, f"argument 'mode' = {sorted(set(modes) - {'SPH', 'RB'})} needs format 'VTK' (format 'DUMP' "
                      "holds the particles only, as Parmec's LAMMPS-style dump)")
        self.outputs.append({"subset": sub, "formats": list(fmts), "entities": entities, "modes": modes})

    def _interval(self, cmd, name, v):
        """An output interval as a function of Parmec's time: a float, an int = a TSERIES number (as in GRAVITY)
        or a callback f(t); evaluated every step, it must be > 0."""
        if _is_real(v) and not isinstance(v, int):
            if not v > 0:
                fail(cmd, f"argument '{name}' must be > 0, got {v!r}")
            return lambda t, c=float(v): c
        kind, val = self._source(cmd, name, v)
        if kind == "tseries":
            ts = self.tseries[val]
            return lambda t: _positive(cmd, name, tseries_value(ts, t), t)
        return lambda t: _positive(cmd, name, val(t), t)

    def default_prefix(self):
        """Output file prefix without DEM(prefix=): the script's name without '.py' (seed)."""
        return os.path.splitext(os.path.basename(self.script))[0] if self.script else "parmec"

    def output_base(self):
        """Path stem of the output files: the prefix in the script's folder (as Parmec's output_path)."""
        folder = os.path.dirname(os.path.abspath(self.script)) if self.script else os.getcwd()
        return os.path.join(folder, self.prefix or self.default_prefix())

    def DEM(self, duration, step, interval=None, prefix=None, adaptive=0.0):
        cmd = "DEM"
        if not _is_real(duration) or duration <= 0:
            fail(cmd, f"argument 'duration' must be a finite number > 0, got {duration!r}")
        if not _is_real(step) or step <= 0:
            fail(cmd, f"argument 'step' must be a finite number > 0, got {step!r}")
        if not _is_real(adaptive) or not 0.0 <= adaptive <= 1.0:
            fail(cmd, f"argument 'adaptive' must be 0 (off) or a reduction factor in (0, 1], got {adaptive!r}")
        if adaptive > 0.0:
            fail(cmd, f"argument 'adaptive' = {adaptive!r} (adaptive time stepping) is not supported: Parmec "
                      "re-estimates the step in every step from the springs and contacts active in it (h_n+1 = "
                      "adaptive x the smallest per-particle estimate, kept within [0.1, 10] h_n) and moves positions "
                      "by (h_n + h_n+1)/2 v; fix parmec/rigid integrates with a constant step. Use a constant "
                      "step = adaptive * CRITICAL() instead")
        if prefix is not None:
            if not isinstance(prefix, str) or not prefix:
                fail(cmd, f"argument 'prefix' must be a non-empty string, got {prefix!r}")
            if self.frozen and prefix != (self.prefix or self.default_prefix()):
                fail(cmd, f"argument 'prefix' = {prefix!r}: the prefix can only change at time 0.0 or after RESET() "
                          f"(seed), it is {self.prefix or self.default_prefix()!r}")
            self.prefix = prefix
        if interval is None:
            interval = float(step)
        if isinstance(interval, (tuple, list)):
            if len(interval) != 2:
                fail(cmd, f"argument 'interval' must be a number, callback or TSERIES number, or a tuple (files, "
                          f"history) of them, got {interval!r}")
            parts = list(interval)
        else:
            parts = [interval, interval]
        files, hist = (self._interval(cmd, name, v) for name, v in zip(("interval[0] (files)", "interval[1] (history)"),
                                                                        parts))
        if not self.particles:
            fail(cmd, "no particles defined")
        from .runner import run_dem
        return run_dem(self, float(duration), float(step), files, hist, prefix)
