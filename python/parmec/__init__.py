"""The Parmec commands as a module, for scripts and helpers written for Parmec (`from parmec import *`,
`from parmec import MESH`): inside a script run by `python -m dembridge.parmec` (or
dembridge.parmec.run_script) every name is that session's command."""
from dembridge.parmec import COMMANDS, ParmecError, current_commands

__all__ = list(COMMANDS)


def __getattr__(name):
    if name in COMMANDS:
        return current_commands()[name]
    raise AttributeError(f"module 'parmec' has no attribute {name!r} (the Parmec commands: {', '.join(COMMANDS)})")


def __dir__():
    return sorted(list(globals()) + __all__)


__all__ += ["ParmecError"]
