"""OUTPUT modes 'SL', 'ST', 'JT' and 'CD': one VTK XML frame of linear springs, torsion springs, joints or
contacts (the seed's entities per mode), from the values the fixes report (fix parmec/spring and
parmec/torsion local arrays, fix parmec/rigid's joint reactions, fix parmec/granular's contact array) and
the particle states of the same frame. Which springs/joints/contacts a file holds ("attached to" the
particles of the OUTPUT call) is decided by the caller (attached())."""
import math

from .vtk_output import write_vtu

SL_ENTITIES = ("NUMBER", "DISPL", "LENGTH", "ORIENT", "F", "SF", "FF", "SS", "PAIR")
ST_ENTITIES = ("NUMBER", "XDIR", "YDIR", "ZDIR", "TRQROT", "TRQTOT", "TRQSPR")
JT_ENTITIES = ("NUMBER", "JREAC")
CD_ENTITIES = ("COLOR", "DISPL", "F", "FN", "FT", "SF", "FF", "AREA", "PAIR")

VTK_VERTEX, VTK_LINE = 1, 3


def _moved(st, X, P):
    """Current place of the referential point P of a body with mass centre X and state st (x, L rows)."""
    return [st["x"][r] + sum(st["L"][r][c] * (P[c] - X[c]) for c in range(3)) for r in range(3)]


def _unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v] if n > 0 else [0.0, 0.0, 0.0]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def attached(pairs, ids):
    """Indices k of pairs[k] = (part1, part2) with part1 or part2 among ids (Parmec: 'data including
    particles' of the OUTPUT call)."""
    s = set(ids)
    return [k for k, (a, b) in enumerate(pairs) if a in s or b in s]


def _pick(want, order):
    return [e for e in order if e in want]


def spring_points(model, s, states):
    """Current (point1, point2, direction) of spring s: points moving with their bodies, point2 spatial for
    part2 = -1, the foot of point1 on the (moving) plane for a point-plane spring; the direction as the
    spring uses it (follower p2 - p1, constant d, planar projection, or the plane normal)."""
    P = model.particles
    p1 = _moved(states[s["part1"]], P[s["part1"]].centre, s["point1"])
    j = s["part2"]
    move = (lambda q: _moved(states[j], P[j].centre, q)) if j >= 0 else (lambda q: list(q))
    if s["plane"] is not None:
        base = move(s["point2"])
        n = _unit([c - b for c, b in zip(move([a + b for a, b in zip(s["point2"], s["plane"])]), base)])
        d = sum((a - b) * c for a, b, c in zip(p1, base, n))
        return p1, [a - d * c for a, c in zip(p1, n)], n
    p2 = move(s["point2"])
    d1 = _unit([b - a for a, b in zip(p1, p2)])
    if "direction" in s:
        d = _unit(s["direction"])
        if s.get("planar"):
            dot = sum(a * b for a, b in zip(d1, d))
            return p1, p2, _unit([a - dot * b for a, b in zip(d1, d)])
        return p1, p2, d
    return p1, p2, d1


def spring_frame(path, model, ks, states, rows, entities):
    """Linear springs ks as VTK lines point1 -> point2 with cell data: NUMBER, DISPL (stroke), LENGTH,
    ORIENT (direction), F, SF, FF, SS, PAIR. rows[k] = fix parmec/spring's (LENGTH, STROKE, F, SF, FF, SS)
    of spring k, or None before its first evaluation (stroke and forces 0)."""
    pts, cells, data = [], [], {e: [] for e in SL_ENTITIES}
    for k in ks:
        s = model.springs[k]
        p1, p2, d = spring_points(model, s, states)
        pts += [p1, p2]
        cells.append([len(pts) - 2, len(pts) - 1])
        row = rows.get(k)
        if row is None:
            code = -1.0 if s["inactive"] else -2.0 if any(k in u["msprings"] for u in model.unsprings) else -3.0
            row = [math.dist(p1, p2), 0.0, 0.0, 0.0, 0.0, code]
        length, stroke, f, sf, ff, ss = row[:6]
        for e, v in (("NUMBER", [k]), ("DISPL", [stroke]), ("LENGTH", [length]), ("ORIENT", d), ("F", [f]),
                     ("SF", [sf]), ("FF", [ff]), ("SS", [ss]), ("PAIR", [s["part1"], s["part2"]])):
            data[e].append(v)
    size = {"ORIENT": 3, "PAIR": 2}
    cdata = [(e, size.get(e, 1), data[e], "Int32" if e in ("NUMBER", "PAIR") else "Float64")
             for e in _pick(entities, SL_ENTITIES)]
    write_vtu(path, pts, cells, VTK_LINE, cell_data=cdata)


def torsion_frame(path, model, ks, states, rows, entities):
    """Torsion springs ks as vertices at refpnt (moving with part1; default the midpoint of the two mass
    centres, or part1's centre when part2 = -1) with NUMBER, XDIR, YDIR, ZDIR, TRQROT, TRQTOT, TRQSPR.
    TRQROT = roll x + pitch y + yaw z, TRQTOT/TRQSPR likewise from their (r, p, y) components, so that
    TRQROT . XDIR = roll as the seed says. rows[k] = fix parmec/torsion's 15 values (ROLL ... ZDIR_Z)."""
    P = model.particles
    pts, data = [], {e: [] for e in ST_ENTITIES}
    for k in ks:
        t = model.torsions[k]
        a, b = t["part1"], t["part2"]
        if "refpnt" in t:
            pts.append(_moved(states[a], P[a].centre, t["refpnt"]))
        elif b >= 0:
            pts.append([0.5 * (states[a]["x"][c] + states[b]["x"][c]) for c in range(3)])
        else:
            pts.append(list(states[a]["x"]))
        row = rows.get(k)
        if row is None:  # before the first evaluation: the reference directions turned with part1
            L = states[a]["L"]
            x = _unit([sum(L[r][c] * t["xdir"][c] for c in range(3)) for r in range(3)])
            z = _unit([sum(L[r][c] * t["zdir"][c] for c in range(3)) for r in range(3)])
            row = [0.0] * 9 + x + z
        x, z = list(row[9:12]), list(row[12:15])
        y = _cross(z, x)

        def spatial(r, p, yw):
            return [r * x[c] + p * y[c] + yw * z[c] for c in range(3)]
        for e, v in (("NUMBER", [k]), ("XDIR", x), ("YDIR", y), ("ZDIR", z), ("TRQROT", spatial(*row[0:3])),
                     ("TRQTOT", spatial(*row[3:6])), ("TRQSPR", spatial(*row[6:9]))):
            data[e].append(v)
    pdata = [(e, 1 if e == "NUMBER" else 3, data[e], "Int32" if e == "NUMBER" else "Float64")
             for e in _pick(entities, ST_ENTITIES)]
    write_vtu(path, pts, [[i] for i in range(len(pts))], VTK_VERTEX, point_data=pdata)


def joint_frame(path, model, ks, states, reactions, entities):
    """Ball joints ks as vertices at the joint point (moving with part1) with NUMBER and JREAC;
    reactions = fix parmec/rigid's [JREAC_X, _Y, _Z, |JREAC|] per joint, or None (zero, before a step)."""
    P = model.particles
    pts, data = [], {e: [] for e in JT_ENTITIES}
    for k in ks:
        a, _, point = model.joints[k]
        pts.append(_moved(states[a], P[a].centre, point))
        data["NUMBER"].append([k])
        data["JREAC"].append(list(reactions[4 * k:4 * k + 3]) if reactions else [0.0, 0.0, 0.0])
    pdata = [(e, 1 if e == "NUMBER" else 3, data[e], "Int32" if e == "NUMBER" else "Float64")
             for e in _pick(entities, JT_ENTITIES)]
    write_vtu(path, pts, [[i] for i in range(len(pts))], VTK_VERTEX, point_data=pdata)


def contact_frame(path, contacts, entities):
    """Contacts as vertices at the contact point with COLOR (2), DISPL (depth), F, FN, FT, SF, FF, AREA and
    PAIR (particle numbers; -1 for an obstacle). contacts: dicts with those keys and 'point'."""
    pts = [c["point"] for c in contacts]
    size = {"COLOR": 2, "PAIR": 2, "F": 3, "FN": 3, "FT": 3}
    pdata = [(e, size.get(e, 1), [c[e] for c in contacts], "Int32" if e in ("COLOR", "PAIR") else "Float64")
             for e in _pick(entities, CD_ENTITIES)]
    write_vtu(path, pts, [[i] for i in range(len(pts))], VTK_VERTEX, point_data=pdata)
