"""Parmec input scripts on LAMMPS + dembridge: `python -m dembridge.parmec model.py [args]`
(doc/parmec_front_end.md). `run_script(path, argv)` runs a script in-process and returns its namespace."""
import os
import runpy  # noqa: F401

from .errors import ParmecError
from .model import Model

__all__ = ["ParmecError", "Model", "run_script"]


def run_script(path, argv=(), quirks=False, workdir=None):
    """Execute the Parmec script at `path` with the Parmec commands defined; returns the script's globals."""
    model = Model(argv=argv, script=path, quirks=quirks, workdir=workdir)
    ns = model.namespace()
    code = compile(open(path).read(), path, "exec")
    cwd = os.getcwd()
    try:
        exec(code, ns)
    finally:
        os.chdir(cwd)
        model.reset_state()
    return ns
