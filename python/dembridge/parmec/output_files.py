"""Which files the OUTPUT calls write (seed: OUTPUT). Group 0 is the particles in no OUTPUT subset, with the
entities/modes of the last OUTPUT call without a subset (the seed's defaults if there is none); group k = 1,
2, ... is the k-th OUTPUT call with a subset. Per group and mode, with format 'VTK', a .pvd time series of
.vtu frames named as Parmec names its files:
  PREFIXkrb   'RB'   every particle of the group (vertex at the mass centre)
  PREFIXksph  'SPH'  the SPHERE particles of the group (same arrays as RB, RADIUS for sphere glyphs)
  PREFIXk     'MESH' boundary triangles of the MESH particles of the group (group 0: and the obstacles,
                     moving ones at the pose fix parmec/granular gives them: compute parmec/obstacles)
  PREFIXksl   'SL'   linear springs attached to a particle of the group (lines point1 -> point2)
  PREFIXkst   'ST'   torsion springs attached to a particle of the group (seed also says 'TS': accepted)
  PREFIXkjt   'JT'   ball joints attached to a particle of the group
  PREFIXkcd   'CD'   contacts involving a particle of the group (written while GRANULAR contact can act)
'attached'/'involving' = part1 or part2 (pair) is in the group, as Parmec selects springs for its files."""
import math
import os

from . import vtk_constraints as vc
from . import vtk_output

ALL_MODES = ("SPH", "MESH", "RB", "CD", "SL", "ST", "JT")
SUFFIX = {"RB": "rb", "SPH": "sph", "MESH": "", "SL": "sl", "ST": "st", "JT": "jt", "CD": "cd"}
DEFAULT = {"subset": None, "entities": None, "modes": None, "formats": ["VTK"]}


def groups(model):
    """[(index, particle ids, OUTPUT spec)] as described in the module docstring."""
    rest = DEFAULT
    subsets = []
    for o in model.outputs:
        if o["subset"] is None:
            rest = o
        else:
            subsets.append(o)
    chosen = {i for o in subsets for i in o["subset"]}
    out = []
    rest_ids = [i for i in range(len(model.particles)) if i not in chosen]
    if rest_ids:
        out.append((0, rest_ids, rest))
    out += [(k + 1, list(o["subset"]), o) for k, o in enumerate(subsets)]
    return out


def needed_modes(model):
    """Modes some group writes in VTK (so the runner knows which fix outputs to dump)."""
    if not model.outputs:
        return set()
    return {m for _, _, o in groups(model) if "VTK" in o["formats"] for m in (o["modes"] or ALL_MODES)}


def contacts(rows):
    """fix parmec/granular local rows (17 columns, FixParmecGranular::kCols) -> dicts of the CD entities:
    F on the first body of PAIR, FN = fn n, FT = F - FN, FF = |FT|, SF = k_n depth, DISPL = depth."""
    out = []
    for r in rows:
        f, fn, n = list(r[8:11]), r[11], list(r[12:15])
        FN = [fn * c for c in n]
        FT = [a - b for a, b in zip(f, FN)]
        out.append({"PAIR": [int(r[0]) - 1, int(r[1]) - 1 if r[1] > 0 else -1], "COLOR": [int(r[2]), int(r[3])],
                    "point": list(r[4:7]), "DISPL": [r[7]], "F": f, "FN": FN, "FT": FT, "SF": [r[15]],
                    "FF": [math.sqrt(sum(c * c for c in FT))], "AREA": [r[16]]})
    return out


def moving(ob):
    return ob["point"] is not None and (ob["linear"] is not None or ob["angular"] is not None)


def obstacles_at(model, rows):
    """The obstacles of one frame as {triangles, colors}: static ones as defined, moving ones from compute
    parmec/obstacles rows (obstacle, colour, 9 coordinates) of that step, or as defined before the first step."""
    posed = {}
    for r in rows:
        ob = posed.setdefault(int(r[0]), {"triangles": [], "colors": []})
        ob["triangles"].append(list(r[2:11]))
        ob["colors"].append(int(r[1]))
    return [posed.get(k, ob) if moving(ob) else ob for k, ob in enumerate(model.obstacles)]


def _frame_writer(mode, model, ids, entities, idx):
    """(writer(path, frame), has_content) for one group and mode; frame = {states, springs, torsions, joints,
    contacts} of one output time."""
    P = model.particles
    if mode in ("RB", "SPH"):
        sel = ids if mode == "RB" else [i for i in ids if P[i].kind == "SPHERE"]
        want = [e for e in (entities or vtk_output.RB_ENTITIES)]
        return (lambda path, fr: vtk_output.rigid_body_frame(path, P, sel, fr["states"], want)), bool(sel)
    if mode == "MESH":
        with_obstacles = idx == 0 and bool(model.obstacles)
        return (lambda path, fr: vtk_output.mesh_frame(
            path, P, ids, fr["states"], entities, obstacles_at(model, fr["obstacles"]) if with_obstacles else [])), \
            any(P[i].kind == "MESH" for i in ids) or with_obstacles
    if mode == "SL":
        ks = vc.attached([(s["part1"], s["part2"]) for s in model.springs], ids)
        want = entities or vc.SL_ENTITIES
        return (lambda path, fr: vc.spring_frame(path, model, ks, fr["states"], fr["springs"], want)), bool(ks)
    if mode == "ST":
        ks = vc.attached([(t["part1"], t["part2"]) for t in model.torsions], ids)
        want = entities or vc.ST_ENTITIES
        return (lambda path, fr: vc.torsion_frame(path, model, ks, fr["states"], fr["torsions"], want)), bool(ks)
    if mode == "JT":
        ks = vc.attached([(a, b) for a, b, _ in model.joints], ids)
        want = entities or vc.JT_ENTITIES
        return (lambda path, fr: vc.joint_frame(path, model, ks, fr["states"], fr["joints"], want)), bool(ks)
    sel = set(ids)
    want = entities or vc.CD_ENTITIES
    return (lambda path, fr: vc.contact_frame(
        path, [c for c in fr["contacts"] if c["PAIR"][0] in sel or c["PAIR"][1] in sel], want)), \
        model.contact_active()


def write_vtk(base, model, frames, entries):
    """Append frames [(time, frame)] to every group's series; entries = {pvd path: [(time, file)]}, kept across
    DEM calls so that each call rewrites complete .pvd files. Returns the .pvd paths written."""
    written = []
    for idx, ids, o in groups(model):
        if "VTK" not in o["formats"]:
            continue
        for mode in (o["modes"] or ALL_MODES):
            writer, has = _frame_writer(mode, model, ids, o["entities"], idx)
            if not has:
                continue
            stem = f"{base}{idx}{SUFFIX[mode]}"
            pvd = stem + ".pvd"
            series = entries.setdefault(pvd, [])
            for t, fr in frames:
                name = f"{os.path.basename(stem)}_{len(series)}.vtu"
                if writer(os.path.join(os.path.dirname(stem) or ".", name), fr) is not False:
                    series.append((t, name))
            if series:
                vtk_output.write_pvd(pvd, series)
                written.append(pvd)
    return written
