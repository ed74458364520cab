"""Parmec input scripts on LAMMPS + dembridge: `python -m dembridge.parmec model.py [args]`
(doc/parmec_front_end.md). `run_script(path, argv)` runs a script in-process and returns its namespace."""
import os
import runpy  # noqa: F401

from .errors import ParmecError
from .model import Model

__all__ = ["ParmecError", "Model", "run_script"]


def run_script(path, argv=(), quirks=False, workdir=None):
    """Execute the Parmec script at `path` with the Parmec commands defined; returns the script's globals.
    quirks: False (corrected), True (upstream Parmec) or "fixedQ1Q3" (every quirk but Q1 and Q3)."""
    if quirks not in (False, True, "fixedQ1Q3"):
        raise ParmecError(f"run_script: quirks must be False, True or 'fixedQ1Q3', got {quirks!r}")
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
