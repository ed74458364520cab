"""HISTORY requests and the values of one sample (spec parmec-springs §1.3, §14)."""
import math

from .errors import fail

PARTICLE = {"PX", "PY", "PZ", "|P|", "DX", "DY", "DZ", "|D|", "VX", "VY", "VZ", "|V|", "OX", "OY", "OZ", "|O|",
            "FX", "FY", "FZ", "|F|", "TX", "TY", "TZ", "|T|"}
SPRING = ["LENGTH", "STROKE", "F", "SF", "FF", "SS"]          # fix parmec/spring local columns 2..7
TORSION = ["ROLL", "PITCH", "YAW", "TRQTOT_R", "TRQTOT_P", "TRQTOT_Y", "TRQSPR_R", "TRQSPR_P", "TRQSPR_Y",
           "XDIR_X", "XDIR_Y", "XDIR_Z", "ZDIR_X", "ZDIR_Y", "ZDIR_Z"]  # fix parmec/torsion columns 2..16
JOINT = ["JREAC_X", "JREAC_Y", "JREAC_Z", "|JREAC|"]


def request(model, entity, source, point):
    cmd = "HISTORY"
    if not isinstance(entity, str):
        fail(cmd, f"argument 'entity' must be a string, got {entity!r}")
    if entity == "TIME":
        kind, ids = "time", []
    elif entity in PARTICLE:
        kind = "particle"
    elif entity in SPRING:
        kind = "spring"
    elif entity in TORSION:
        kind = "torsion"
    elif entity in JOINT:
        kind = "joint"
    else:
        fail(cmd, f"unknown entity {entity!r}")
    if kind != "time":
        if isinstance(source, tuple):
            fail(cmd, "argument 'source': spatial sphere/box sources are not supported")
        ids = list(source) if isinstance(source, list) else [source]
        n = {"particle": len(model.particles), "spring": len(model.springs), "torsion": len(model.torsions),
             "joint": len(model.joints)}[kind]
        for i in ids:
            if not isinstance(i, int) or isinstance(i, bool) or not 0 <= i < n:
                fail(cmd, f"argument 'source': {i!r} is not a {kind} number (0 ... {n - 1}) for entity '{entity}'")
        if not ids:
            fail(cmd, "argument 'source' is an empty list")
    if point is not None:
        if kind != "particle" or len(ids) != 1:
            fail(cmd, "argument 'point' needs a particle entity and a single particle source")
        if not isinstance(point, (tuple, list)) or len(point) != 3:
            fail(cmd, f"argument 'point' must be a tuple (x, y, z), got {point!r}")
        point = [float(c) for c in point]
    out = []
    model.histories.append({"entity": entity, "kind": kind, "ids": ids, "point": point, "list": out})
    return out


def particle_value(model, entity, i, st, point):
    """One particle entity from a state dict st = {x, v, w, f, t, L (rows)} (current values)."""
    p = model.particles[i]
    name, comp = entity.lstrip("|").rstrip("|")[0], entity[-1]
    x = st["x"]
    if point is not None:
        arm = [sum(st["L"][r][c] * (point[c] - p.centre[c]) for c in range(3)) for r in range(3)]
    if name == "P":
        vec = x if point is None else [x[c] + arm[c] for c in range(3)]
    elif name == "D":
        vec = [x[c] - p.centre[c] for c in range(3)] if point is None else \
            [x[c] + arm[c] - point[c] for c in range(3)]
    elif name == "V":
        vec = st["v"]
        if point is not None:
            w = st["w"]
            a, b = (arm, w) if model.quirks else (w, arm)  # Q25: Parmec adds a × ω
            vec = [vec[0] + a[1] * b[2] - a[2] * b[1], vec[1] + a[2] * b[0] - a[0] * b[2],
                   vec[2] + a[0] * b[1] - a[1] * b[0]]
    elif name == "O":
        vec = st["w"]
    elif name == "F":
        vec = st["f"]
    else:
        vec = st["t"]
    if entity.startswith("|"):
        return math.sqrt(sum(c * c for c in vec))
    return vec["XYZ".index(comp)]
