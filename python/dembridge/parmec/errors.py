"""The one exception the Parmec front end raises for bad or unsupported input."""


class ParmecError(ValueError):
    """A Parmec command or argument that is invalid or not supported; the message names both."""


def fail(command, message):
    raise ParmecError(f"{command}: {message}")
