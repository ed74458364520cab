"""Parmec input scripts on LAMMPS + dembridge: `python -m dembridge.parmec model.py [args]`
(doc/parmec_front_end.md). `run_script(path, argv)` runs a script in-process and returns its namespace."""
import os

from .errors import ParmecError
from .model import COMMANDS, Model

__all__ = ["ParmecError", "Model", "run_script", "COMMANDS", "current_commands"]

_sessions = []  # namespaces of the scripts being run (innermost last): what `import parmec` hands out


def current_commands():
    """The Parmec commands of the script being run (the `parmec` module's names)."""
    if not _sessions:
        raise ParmecError("parmec: the Parmec commands exist only while a script runs (python -m dembridge.parmec "
                          "model.py, or dembridge.parmec.run_script)")
    return _sessions[-1]


def run_script(path, argv=(), quirks=False, workdir=None):
    """Execute the Parmec script at `path` with the Parmec commands defined; returns the script's globals.
    quirks: False (corrected), True (upstream Parmec) or "fixedQ1Q3" (every quirk but Q1 and Q3)."""
    if quirks not in (False, True, "fixedQ1Q3"):
        raise ParmecError(f"run_script: quirks must be False, True or 'fixedQ1Q3', got {quirks!r}")
    model = Model(argv=argv, script=path, quirks=quirks, workdir=workdir)
    ns = model.namespace()
    code = compile(open(path).read(), path, "exec")
    cwd = os.getcwd()
    _sessions.append({n: ns[n] for n in COMMANDS})
    try:
        exec(code, ns)
    finally:
        _sessions.pop()
        os.chdir(cwd)
        model.reset_state()
    return ns
